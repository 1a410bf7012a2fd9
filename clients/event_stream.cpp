#include "clients/event_stream.h"

namespace bumprad {

std::vector<ServerEvent> EventStreamParser::feed(std::string_view bytes) {
  pending_ += bytes;
  std::vector<ServerEvent> out;
  std::size_t start = 0, end;
  while ((end = pending_.find('\n', start)) != std::string::npos) {
    std::string_view line(pending_.data() + start, end - start);
    if (line.ends_with('\r')) line.remove_suffix(1);
    start = end + 1;
    if (line.empty()) {  // a blank line ends the event
      if (!event_.data.empty()) {
        if (event_.data.back() == '\n') event_.data.pop_back();
        out.push_back(std::move(event_));
      }
      event_ = {};
      continue;
    }
    if (line.front() == ':') continue;  // a comment: keep-alive
    auto colon = line.find(':');
    std::string_view field = line.substr(0, colon);
    std::string_view value = colon == std::string_view::npos ? "" : line.substr(colon + 1);
    if (value.starts_with(' ')) value.remove_prefix(1);
    if (field == "event")
      event_.name = value;
    else if (field == "data")
      event_.data += std::string(value) + "\n";
  }
  pending_.erase(0, start);
  return out;
}

}  // namespace bumprad
