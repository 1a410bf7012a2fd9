// Server-Sent Events parsing: events split anywhere across reads, comments, CRLF lines.
#include "clients/event_stream.h"

#include <gtest/gtest.h>

namespace bumprad {
namespace {

TEST(EventStream, EventsSplitAcrossReadsComeOutWhole) {
  const std::string text =
      "retry: 3000\nevent: state\ndata: {\"a\":1}\n\n: keep-alive\n\n"
      "id: 2\r\nevent: step\r\ndata: one\r\ndata: two\r\n\r\ndata: plain\n\n";
  for (std::size_t piece = 1; piece <= text.size(); ++piece) {
    EventStreamParser parser;
    std::vector<ServerEvent> events;
    for (std::size_t at = 0; at < text.size(); at += piece)
      for (auto& e : parser.feed(std::string_view(text).substr(at, piece))) events.push_back(e);
    ASSERT_EQ(events.size(), 3u) << "piece " << piece;
    EXPECT_EQ(events[0].name, "state");
    EXPECT_EQ(events[0].data, "{\"a\":1}");
    EXPECT_EQ(events[1].name, "step");
    EXPECT_EQ(events[1].data, "one\ntwo");
    EXPECT_EQ(events[2].name, "message");
    EXPECT_EQ(events[2].data, "plain");
  }
}

TEST(EventStream, AnUnfinishedEventWaits) {
  EventStreamParser parser;
  EXPECT_TRUE(parser.feed("event: done\ndata: {}\n").empty());
  auto events = parser.feed("\n");
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].name, "done");
}

}  // namespace
}  // namespace bumprad
