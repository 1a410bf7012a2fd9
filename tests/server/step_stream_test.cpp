// What a viewer of a job is sent: Server-Sent Events and multipart PNG frames, caught up to
// the newest step, ended once with the job's end state.
#include "server/step_stream.h"

#include <gtest/gtest.h>

namespace bumprad {
namespace {

Job::View view(int step, JobState state, const char* png) {
  JobRecord r;
  r.id = "0123456789abcdef";
  r.step = step;
  r.state = state;
  return {r, png ? std::make_shared<const std::string>(png) : nullptr};
}

TEST(StepStream, EventsStartWithTheStateThenStepsThenTheEnd) {
  StepStream s(StreamRequest::Kind::Events);
  EXPECT_EQ(s.content_type(), "text/event-stream");
  std::string first = s.catch_up(view(0, JobState::Running, nullptr));
  EXPECT_EQ(first.rfind("retry: 3000\nevent: state\ndata: {", 0), 0u) << first;
  EXPECT_EQ(s.catch_up(view(0, JobState::Running, nullptr)), "");
  // A viewer that fell behind gets the newest step only.
  std::string step = s.catch_up(view(3, JobState::Running, "png3"));
  EXPECT_EQ(step.rfind("id: 3\nevent: step\n", 0), 0u) << step;
  EXPECT_NE(step.find("/steps/3.png"), std::string::npos);
  EXPECT_FALSE(s.finished());
  std::string end = s.catch_up(view(4, JobState::Done, "png4"));
  EXPECT_NE(end.find("event: step\n"), std::string::npos);
  EXPECT_NE(end.find("event: done\n"), std::string::npos);
  EXPECT_TRUE(s.finished());
  EXPECT_EQ(s.catch_up(view(4, JobState::Done, "png4")), "");
  EXPECT_EQ(s.heartbeat(), ": keep-alive\n\n");
}

// Each frame ends with the delimiter after it, which is when a browser shows it (a frame
// that waited for the next one's boundary showed each step one step late); the end closes
// with the newest frame again.
TEST(StepStream, ImagesAreFramesOfTheNewestPreviewEachClosedAtOnce) {
  StepStream s(StreamRequest::Kind::Images);
  EXPECT_EQ(s.catch_up(view(0, JobState::Queued, nullptr)), "--bumpradframe\r\n");
  std::string frame = s.catch_up(view(2, JobState::Running, "PNGDATA"));
  EXPECT_EQ(frame,
            "Content-Type: image/png\r\nContent-Length: 7\r\n"
            "X-Bumprad-Step: 2\r\n\r\nPNGDATA\r\n--bumpradframe\r\n");
  EXPECT_EQ(s.catch_up(view(2, JobState::Running, "PNGDATA")), "");
  EXPECT_EQ(s.catch_up(view(2, JobState::Cancelled, "PNGDATA")),
            "Content-Type: image/png\r\nContent-Length: 7\r\n"
            "X-Bumprad-Step: 2\r\n\r\nPNGDATA\r\n--bumpradframe--\r\n");
  EXPECT_TRUE(s.finished());
  EXPECT_EQ(s.heartbeat(), "");

  StepStream done(StreamRequest::Kind::Images);  // opened on a finished job
  EXPECT_EQ(done.catch_up(view(3, JobState::Done, "PNG")),
            "--bumpradframe\r\nContent-Type: image/png\r\nContent-Length: 3\r\n"
            "X-Bumprad-Step: 3\r\n\r\nPNG\r\n--bumpradframe--\r\n");
}

}  // namespace
}  // namespace bumprad
