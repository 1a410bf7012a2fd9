// Server-Sent Events from a byte stream (the WHATWG event-stream format, the parts bumprad
// sends): feed it pieces as they arrive and get whole events back.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace bumprad {

struct ServerEvent {
  std::string name = "message";
  std::string data;
};

class EventStreamParser {
 public:
  // The events completed by `bytes`; a partial one waits for the next piece.
  std::vector<ServerEvent> feed(std::string_view bytes);

 private:
  std::string pending_;
  ServerEvent event_;
};

}  // namespace bumprad
