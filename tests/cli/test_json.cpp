// Tests of the CLI's JSON writer: string escaping, numbers, nesting; checked by a strict reader.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "cli/json.hpp"
#include "cli/json_check.hpp"

namespace {

using fdmsurf::cli::json_number;
using fdmsurf::cli::json_quote;
using fdmsurf::cli::JsonWriter;
using fdmsurf_cli_test::JsonValue;
using fdmsurf_cli_test::parse_json;

// The string that reading json_quote(text) back gives.
std::string round_trip(const std::string& text) {
    const auto value = parse_json(json_quote(text));
    EXPECT_TRUE(value) << json_quote(text);
    if (!value) return {};
    EXPECT_EQ(value->type, JsonValue::Type::String);
    return value->string;
}

TEST(CliJson, QuotesAndEscapes) {
    EXPECT_EQ(json_quote(""), "\"\"");
    EXPECT_EQ(json_quote("plain"), "\"plain\"");
    EXPECT_EQ(json_quote("a\"b\\c"), "\"a\\\"b\\\\c\"");
    EXPECT_EQ(json_quote("\n\r\t\b\f"), "\"\\n\\r\\t\\b\\f\"");
    EXPECT_EQ(json_quote(std::string("\x01\x1f", 2)), "\"\\u0001\\u001f\"");
    EXPECT_EQ(json_quote(std::string(1, '\0')), "\"\\u0000\"");
    EXPECT_EQ(json_quote("/"), "\"/\"");
}

TEST(CliJson, ValidUtf8PassesThrough) {
    for (const std::string text : {"Å²", "σ = 3 Å", "日本", "\xf0\x9f\x98\x80", "\x7f"}) {
        EXPECT_EQ(json_quote(text), "\"" + text + "\"");
        EXPECT_EQ(round_trip(text), text);
    }
}

TEST(CliJson, InvalidUtf8BecomesReplacementCharacters) {
    EXPECT_EQ(json_quote("a\xff"
                         "b"),
              "\"a\\ufffdb\"");
    EXPECT_EQ(json_quote("\xc3"), "\"\\ufffd\"");                        // truncated sequence
    EXPECT_EQ(json_quote("\xc0\xaf"), "\"\\ufffd\\ufffd\"");             // overlong '/'
    EXPECT_EQ(json_quote("\xed\xa0\x80"), "\"\\ufffd\\ufffd\\ufffd\"");  // surrogate
    EXPECT_EQ(json_quote("\xf4\x90\x80\x80"), "\"\\ufffd\\ufffd\\ufffd\\ufffd\"");  // > 10FFFF
    EXPECT_EQ(json_quote("\x80"), "\"\\ufffd\"");  // lone continuation byte
    EXPECT_EQ(round_trip("x\xfey"), "x\xef\xbf\xbdy");
}

TEST(CliJson, EveryByteGivesValidJson) {
    for (int c = 0; c < 256; ++c) {
        std::string text = "a";  // built by appends: "a" + ... + "b" trips GCC 12's -Wrestrict
        text += static_cast<char>(c);
        text += 'b';
        EXPECT_TRUE(parse_json(json_quote(text))) << c;
    }
}

TEST(CliJson, NumbersAreShortestAndFinite) {
    EXPECT_EQ(json_number(0.5), "0.5");
    EXPECT_EQ(json_number(0.179f), "0.179");
    EXPECT_EQ(json_number(2312.4), "2312.4");
    EXPECT_EQ(json_number(-1.0), "-1");
    EXPECT_EQ(json_number(std::numeric_limits<double>::quiet_NaN()), "null");
    EXPECT_EQ(json_number(std::numeric_limits<float>::infinity()), "null");
    EXPECT_EQ(json_number(-std::numeric_limits<double>::infinity()), "null");
    for (double v : {1e-7, 1e300, 123456789.125, -0.0}) {
        const auto value = parse_json(json_number(v));
        ASSERT_TRUE(value) << json_number(v);
        EXPECT_EQ(value->number, v);
    }
}

TEST(CliJson, WriterNestsAndSeparates) {
    JsonWriter w;
    w.begin_object();
    w.member("name", "x\"y");
    w.member("count", std::size_t{3});
    w.member("negative", -2);
    w.member("ok", true);
    w.member("ratio", 0.25);
    w.key("none").value(nullptr);
    w.key("dims").begin_array();
    for (std::uint32_t d : {1u, 2u, 3u}) w.value(d);
    w.end_array();
    w.key("empty").begin_array().end_array();
    w.key("inner").begin_object().member("a", 1).end_object();
    w.key("nothing").begin_object().end_object();
    w.end_object();
    EXPECT_EQ(w.str(),
              R"({"name":"x\"y","count":3,"negative":-2,"ok":true,"ratio":0.25,"none":null,)"
              R"("dims":[1,2,3],"empty":[],"inner":{"a":1},"nothing":{}})");
    const auto value = parse_json(w.str());
    ASSERT_TRUE(value);
    ASSERT_NE(value->find("dims"), nullptr);
    EXPECT_EQ(value->find("dims")->array.size(), 3u);
    EXPECT_EQ(value->find("name")->string, "x\"y");
}

TEST(CliJson, StringOverloadsAreNotBooleans) {
    JsonWriter w;
    w.begin_array().value("text").value(std::string("s")).value(std::string_view("v"));
    w.end_array();
    EXPECT_EQ(w.str(), R"(["text","s","v"])");
}

TEST(CliJsonCheck, RejectsMalformedJson) {
    for (const char* text :
         {"", "{", "{\"a\":}", "[1,]", "{\"a\":1,}", "01", "1.", ".5", "+1", "nan", "\"\x01\"",
          "\"\\x\"", "\"\\ud800\"", "{} {}", "'a'", "{a:1}", "tru"}) {
        EXPECT_FALSE(parse_json(text)) << text;
    }
    for (const char* text : {"{}", "[]", "0", "-0.5e-3", "\"\\u00e5\"", " {\"a\" : [ null ] } ",
                             "\"\\ud83d\\ude00\""}) {
        EXPECT_TRUE(parse_json(text)) << text;
    }
}

}  // namespace
