#include "server/step_stream.h"

namespace bumprad {
namespace {

constexpr std::string_view kBoundary = "bumpradframe";

std::string event(std::string_view name, const std::string& data) {
  return "event: " + std::string(name) + "\ndata: " + data + "\n\n";
}

}  // namespace

std::string_view StepStream::content_type() const {
  return kind_ == StreamRequest::Kind::Events ? "text/event-stream"
                                              : "multipart/x-mixed-replace; boundary=bumpradframe";
}

std::string StepStream::catch_up(const Job::View& view) {
  if (finished_) return {};
  const JobRecord& r = view.record;
  std::string out;
  if (kind_ == StreamRequest::Kind::Events) {
    if (!started_) out += "retry: 3000\n" + event("state", job_to_json(r));
    if (r.step > sent_step_)
      out += "id: " + std::to_string(r.step) + "\n" + event("step", step_event_json(r));
    if (is_finished(r.state)) out += event(to_string(r.state), job_to_json(r));
  } else {
    // A browser shows a part once it sees the delimiter after it, so each frame ends with
    // one: the next part's ("--B"), or the closing one ("--B--") when the job has ended.
    // A job that ends after its last frame went out closes with that frame again, so the
    // open part is never empty.
    const bool fresh = view.preview && r.step > sent_step_;
    const bool finished = is_finished(r.state);
    if (!started_) out += "--" + std::string(kBoundary) + "\r\n";
    if (view.preview && (fresh || (finished && started_))) {
      out += "Content-Type: image/png\r\nContent-Length: " + std::to_string(view.preview->size()) +
             "\r\nX-Bumprad-Step: " + std::to_string(r.step) + "\r\n\r\n";
      out += *view.preview;
      out += "\r\n--" + std::string(kBoundary) + (finished ? "--\r\n" : "\r\n");
    } else if (finished) {  // no frame at all: an empty stream, closed
      out += "Content-Type: text/plain\r\nContent-Length: 0\r\n\r\n\r\n--" +
             std::string(kBoundary) + "--\r\n";
    }
  }
  started_ = true;
  sent_step_ = view.preview || kind_ == StreamRequest::Kind::Events ? r.step : sent_step_;
  finished_ = is_finished(r.state);
  return out;
}

std::string StepStream::heartbeat() const {
  return kind_ == StreamRequest::Kind::Events ? ": keep-alive\n\n" : "";
}

}  // namespace bumprad
