// multipart/form-data as curl -F and browsers write it, and the bodies that are not.
#include "protocol/multipart.h"

#include <gtest/gtest.h>

namespace bumprad {
namespace {

const std::string kType = "multipart/form-data; boundary=----x1";

TEST(Multipart, PartsKeepTheirNamesFileNamesAndBytes) {
  // A preamble, a plain field, a file whose bytes hold CRLFs and a near-boundary, an epilogue.
  using namespace std::string_literals;
  const std::string body =
      "ignored preamble\r\n"
      "------x1\r\n"
      "Content-Disposition: form-data; name=\"scene\"\r\n"
      "\r\n"
      "{\"objects\": []}\r\n"
      "------x1\r\n"
      "content-disposition: FORM-DATA; name=file; filename=\"room \\\"1\\\".glb\"\r\n"
      "Content-Type: model/gltf-binary\r\n"
      "\r\n"
      "a\r\n\r\nb\r\n----x\0c\r\n"s +
      "------x1--\r\n"
      "epilogue";
  const auto parts = parse_multipart(kType, body);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].name, "scene");
  EXPECT_EQ(parts[0].filename, "");
  EXPECT_EQ(parts[0].body, "{\"objects\": []}");
  EXPECT_EQ(parts[1].name, "file");
  EXPECT_EQ(parts[1].filename, "room \"1\".glb");
  EXPECT_EQ(parts[1].body, "a\r\n\r\nb\r\n----x\0c"s);
  EXPECT_EQ(
      media_type_parameter("multipart/form-data; charset=utf-8; boundary=\"a b\"", "boundary"),
      "a b");
}

TEST(Multipart, MalformedBodiesSayWhatIsWrong) {
  const auto error = [](const std::string& type, const std::string& body) {
    try {
      parse_multipart(type, body);
    } catch (const MalformedBody& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error("multipart/form-data", ""),
            "multipart/form-data needs a boundary of 1 to 70 characters");
  EXPECT_EQ(error(kType, "no boundary here"), "the form's boundary never appears in the body");
  EXPECT_EQ(error(kType, "------x1\r\nContent-Disposition: form-data; name=a\r\n\r\nbytes"),
            "part 1 never ends (the closing boundary is missing)");
  EXPECT_EQ(error(kType, "------x1\r\nContent-Type: text/plain\r\n\r\nbytes\r\n------x1--"),
            "part 1: needs Content-Disposition: form-data with a name");
  EXPECT_EQ(error(kType, "------x1\r\nno colon\r\n\r\nbytes\r\n------x1--"),
            "part 1: a header line without a colon");
  EXPECT_EQ(error(kType, "------x1junk\r\n"), "part 1: a boundary must end its line");
}

}  // namespace
}  // namespace bumprad
