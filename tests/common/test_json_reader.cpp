// The one strict JSON reader (common/json_reader.h) shared by edit files and sessions.
#include "freeform/common/error.h"
#include "freeform/common/json_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

using namespace freeform;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

TEST(JsonReader, ParseErrorsNameLineAndColumn) {
  EXPECT_THAT([] { parse_json_text("{\n  \"a\": 1,\n  \"b\": ]\n}", "f.json"); },
              ThrowsMessage<IoError>(HasSubstr("f.json:3: malformed JSON at column 8")));
  EXPECT_THAT([] { parse_json_text("{\"a\": 1e999}", "f.json"); }, ThrowsMessage<IoError>(HasSubstr("f.json")));
  EXPECT_THAT([] { parse_json_text(R"({"x": {"a": 1, "a": 2}})", "f.json"); },
              ThrowsMessage<InvalidInput>(HasSubstr("f.json: the key \"a\" appears twice in one object")));
  // nlohmann's parser stops at a NUL: text after it must not be ignored silently.
  using namespace std::string_literals;
  EXPECT_THAT([] { parse_json_text("{\"a\": 1}\n\0garbage"s, "f.json"); },
              ThrowsMessage<IoError>(HasSubstr("f.json:2: NUL byte at column 1")));
  // The same key in sibling objects is fine; key order is kept.
  const Json j = parse_json_text(R"({"z": {"a": 1}, "y": {"a": 2}})", "f.json");
  EXPECT_EQ(j.begin().key(), "z");
}

TEST(JsonReader, TypedGettersRefuseWhatIsWrongAndNameThePath) {
  const JsonReader r("f.json");
  const Json j = parse_json_text(R"({"n": 1.5, "i": 7, "b": true, "s": "x", "v": [1, 2, 3],
                                     "m": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]})", "f.json");
  EXPECT_EQ(r.number(j["n"], "n"), 1.5);
  EXPECT_EQ(r.integer(j["i"], "i"), 7);
  EXPECT_TRUE(r.boolean(j["b"], "b"));
  EXPECT_EQ(r.string(j["s"], "s"), "x");
  // A path cut at a NUL would name another file.
  EXPECT_THAT([&] { r.string(Json(std::string("a.sel\0.junk", 11)), "sel"); },
              ThrowsMessage<InvalidInput>(HasSubstr("f.json: \"sel\" contains a NUL byte")));
  EXPECT_EQ(r.vec3(j["v"], "v"), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(r.matrix4(j["m"], "m"), Eigen::Matrix4d::Identity());
  EXPECT_THAT([&] { r.integer(j["n"], "a.n"); }, ThrowsMessage<InvalidInput>(HasSubstr("f.json: \"a.n\" must be an integer, got the number 1.5")));
  EXPECT_THAT([&] { r.vec3(j["m"], "m"); }, ThrowsMessage<InvalidInput>(HasSubstr("\"m\" must be an array of 3 numbers")));
  EXPECT_THAT([&] { r.matrix4(j["v"], "v"); }, ThrowsMessage<InvalidInput>(HasSubstr("\"v\" must be 4 rows of 4 numbers")));
  EXPECT_THAT([&] { r.keys(j, "", {"n", "i"}); }, ThrowsMessage<InvalidInput>(HasSubstr("unknown key \"b\" (allowed here: \"n\", \"i\")")));
  EXPECT_THAT([&] { r.required(j, "top", "q"); }, ThrowsMessage<InvalidInput>(HasSubstr("missing required key \"top.q\"")));
  // Non-finite numbers (possible in a document built in code) are refused everywhere.
  const Json inf = std::numeric_limits<double>::infinity();
  EXPECT_THAT([&] { r.number(inf, "x"); }, ThrowsMessage<InvalidInput>(HasSubstr("\"x\" must be finite")));
  EXPECT_THROW(r.vec3(Json::array({1.0, inf, 0.0}), "v"), InvalidInput);
}

TEST(JsonReader, TextRoundTripsDoublesAndExpandsOnlyTheFirstLevels) {
  const Json j = {{"a", 0.1 + 0.2}, {"list", {1, 2, 3}}, {"nested", {{"deep", {{"x", 1}}}}}};
  const std::string text = json_text(j, 1);
  EXPECT_EQ(text, "{\n  \"a\": 0.30000000000000004,\n  \"list\": [1,2,3],\n  \"nested\": {\"deep\":{\"x\":1}}\n}\n");
  EXPECT_EQ(parse_json_text(text, "t")["a"].get<double>(), 0.1 + 0.2);
}
