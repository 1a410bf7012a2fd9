// The service under hostile input and faults, through real sockets against the real
// `bumprad serve`: requests built to crash it, hold it hostage or confuse its parser each get
// a clear answer, and the server keeps serving everyone else.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/raw_connection.h"
#include "tests/test_files.h"
#include "tests/test_server.h"

namespace bumprad {
namespace {

using json = nlohmann::json;
using test::RawConnection;
using test::ServerProcess;

void expect_problem(const HttpResponse& r, int status, const std::string& detail_part,
                    const std::string& field = "") {
  EXPECT_EQ(r.status, status) << r.body;
  EXPECT_EQ(r.header("content-type"), "application/problem+json");
  json p = json::parse(r.body);
  EXPECT_NE(p["detail"].get<std::string>().find(detail_part), std::string::npos) << r.body;
  if (!field.empty()) {
    EXPECT_EQ(p.value("field", ""), field) << r.body;
  }
}

std::string nested(const std::string& open, const std::string& close, int depth) {
  std::string s;
  for (int i = 0; i < depth; ++i) s += open;
  s += "1";
  for (int i = 0; i < depth; ++i) s += close;
  return s;
}

// Before: ~600 KB of brackets under "scene", "solver" or "preview_every" overflowed the
// stack when the value was copied, and the server died with every stream it had.
TEST(HostileInput, DeeplyNestedJsonGets400AndTheServerLives) {
  ServerProcess server(test::fresh_temp_dir("hostile"));
  HttpClient c = server.client();
  for (const std::string key : {"scene", "solver", "preview_every", "bumps"})
    for (const auto& [open, close] :
         {std::pair<std::string, std::string>{"[", "]"}, {"{\"a\":", "}"}}) {
      std::string body = "{\"" + key + "\": " + nested(open, close, 150000) + "}";
      expect_problem(c.request("POST", "/v1/jobs", body), 400, "nested deeper than 32");
    }
  EXPECT_EQ(c.get("/healthz").status, 200);
}

// Before: a request path or body with bytes that are not UTF-8 got 500 (the message quoting
// them could not be written as JSON).
TEST(HostileInput, InvalidUtf8IsQuotedEscaped) {
  ServerProcess server(test::fresh_temp_dir("hostile"));
  HttpClient c = server.client();
  expect_problem(c.request("POST", "/v1/jobs", "{\"builtin\": \"\xff\xfe\"}"), 400,
                 "malformed JSON");
  expect_problem(c.request("POST", "/v1/jobs", "\xc0\xaf"), 400, "malformed JSON");
  HttpResponse r = c.get("/v1/\xff\xc3(x");
  expect_problem(r, 404, "/v1/\\xFF\\xC3(x");
  EXPECT_EQ(c.get("/v1/jobs/\xe2\x82").status, 404);
  EXPECT_EQ(c.get("/healthz").status, 200);
}

// Before: the bytes of a second request that arrived with the first were thrown away, so
// pipelined requests went unanswered or were parsed from their middle.
TEST(HostileInput, PipelinedRequestsAreAllAnsweredInOrder) {
  ServerProcess server(test::fresh_temp_dir("hostile"));
  RawConnection raw(server.port());
  raw.send(
      "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n"
      "GET /v1/jobs/0123456789abcdef HTTP/1.1\r\nHost: x\r\n\r\n"
      "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Length: 2\r\n\r\n{}"
      "GET /v1/scenes HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  auto replies = test::split_responses(raw.read_all());
  ASSERT_EQ(replies.size(), 4u);
  EXPECT_EQ(replies[0].status, 200);
  EXPECT_EQ(replies[0].body, "{\"status\":\"ok\"}");
  EXPECT_EQ(replies[1].status, 404);
  EXPECT_EQ(replies[2].status, 422);
  EXPECT_EQ(replies[3].status, 200);
  EXPECT_NE(replies[3].body.find("wrinkled-box"), std::string::npos);
}

// Before: HEAD got 405 with a body.
TEST(HostileInput, HeadAnswersAsGetWithoutTheBody) {
  ServerProcess server(test::fresh_temp_dir("hostile"));
  HttpResponse get = server.client().get("/v1/scenes");
  RawConnection raw(server.port());
  raw.send(
      "HEAD /v1/scenes HTTP/1.1\r\nHost: x\r\n\r\n"
      "HEAD /v1/jobs/0123456789abcdef/events HTTP/1.1\r\nHost: x\r\n\r\n"
      "GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  auto replies = test::split_responses(raw.read_all(), {true, true, false});
  ASSERT_EQ(replies.size(), 3u);
  EXPECT_EQ(replies[0].status, 200);
  EXPECT_NE(replies[0].head.find("Content-Length: " + std::to_string(get.body.size())),
            std::string::npos)
      << replies[0].head;
  EXPECT_EQ(replies[0].body, "") << "no body came after the head";
  EXPECT_EQ(replies[1].status, 404);
  EXPECT_EQ(replies[2].status, 200);
  EXPECT_EQ(replies[2].body, "{\"status\":\"ok\"}");
}

}  // namespace
}  // namespace bumprad
