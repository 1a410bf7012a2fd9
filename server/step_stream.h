// What one viewer of a job has been sent, and the bytes that bring it up to date: Server-Sent
// Events (a first event at once, one per step, a final one named for the end state) or a
// multipart/x-mixed-replace stream of PNGs ending after the final image. A viewer that falls
// behind skips to the newest step, so it never makes the solver wait or memory grow.
#pragma once

#include <string>
#include <string_view>

#include "server/api.h"
#include "server/job.h"

namespace bumprad {

class StepStream {
 public:
  explicit StepStream(StreamRequest::Kind kind) : kind_(kind) {}

  std::string_view content_type() const;
  // The bytes to send now for the job as `view` shows it; empty when there is nothing new.
  std::string catch_up(const Job::View& view);
  // Sent while idle, so proxies and browsers keep the connection (events only; empty for
  // images, whose viewers wait quietly).
  std::string heartbeat() const;
  // The job's end has been written: close the connection.
  bool finished() const { return finished_; }

 private:
  StreamRequest::Kind kind_;
  bool started_ = false;
  bool finished_ = false;
  int sent_step_ = 0;
};

}  // namespace bumprad
