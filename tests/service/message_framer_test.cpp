#include "service/message_framer.h"

#include <gtest/gtest.h>

namespace hfts::service {
namespace {

std::vector<std::string> frame(MessageFramer& framer, std::string_view bytes) {
  std::vector<std::string> out;
  EXPECT_TRUE(framer.feed(bytes, out));
  return out;
}

using Messages = std::vector<std::string>;

TEST(MessageFramer, SplitsLines) {
  MessageFramer f(1024);
  EXPECT_EQ(frame(f, "abc\ndef\r\n"), (Messages{"abc", "def\r"}));
}

TEST(MessageFramer, JoinsAMessageSplitAcrossReads) {
  MessageFramer f(1024);
  EXPECT_TRUE(frame(f, "{\"a\": [1, ").empty());
  EXPECT_TRUE(frame(f, "2").empty());
  EXPECT_EQ(frame(f, "]}\n"), Messages{"{\"a\": [1, 2]}"});
}

TEST(MessageFramer, HandsOnACompleteTextWithoutNewline) {
  MessageFramer f(1024);
  EXPECT_EQ(frame(f, "{\"m\": \"x\"}"), Messages{"{\"m\": \"x\"}"});
  EXPECT_TRUE(frame(f, "  \r\n").empty()) << "the rest of its line is not an empty message";
  EXPECT_EQ(frame(f, "[1,[2]][3]"), (Messages{"[1,[2]]", "[3]"}));
}

TEST(MessageFramer, IgnoresBracketsInStrings) {
  MessageFramer f(1024);
  EXPECT_TRUE(frame(f, R"({"s": "}]\"}")").empty());
  EXPECT_EQ(frame(f, "}"), Messages{R"({"s": "}]\"}"})"});
}

TEST(MessageFramer, HandsOnEmptyAndBlankLines) {
  MessageFramer f(1024);
  EXPECT_EQ(frame(f, "\n \t\r\n"), (Messages{"", ""}));
}

TEST(MessageFramer, ANewlineEndsATruncatedText) {
  MessageFramer f(1024);
  EXPECT_EQ(frame(f, "{\"a\": \n{}"), (Messages{"{\"a\": ", "{}"}));
}

TEST(MessageFramer, ScalarsAndGarbageWaitForTheNewline) {
  MessageFramer f(1024);
  EXPECT_TRUE(frame(f, std::string("12 \x01\xff", 5)).empty());
  EXPECT_EQ(frame(f, "}\n"), Messages{std::string("12 \x01\xff}", 6)});
}

TEST(MessageFramer, RejectsAMessageOverTheLimit) {
  MessageFramer f(8);
  std::vector<std::string> out;
  EXPECT_TRUE(f.feed("12345678\n", out)) << "exactly the limit is fine";
  EXPECT_FALSE(f.feed("123456789", out));
  EXPECT_FALSE(f.feed("\n", out)) << "the framer stays spent";
  EXPECT_EQ(out, Messages{"12345678"});
}

TEST(MessageFramer, CountsBytesNotYetFramedAgainstTheLimit) {
  MessageFramer f(10);
  std::vector<std::string> out;
  EXPECT_TRUE(f.feed("[[[[[", out));
  EXPECT_FALSE(f.feed("[[[[[[", out));
}

TEST(MessageFramer, ReturnsTheIncompleteRemainder) {
  MessageFramer f(1024);
  EXPECT_TRUE(frame(f, "{}\n  {\"a\":").size() == 1);
  EXPECT_EQ(f.takeRemainder(), "  {\"a\":");
  EXPECT_EQ(f.takeRemainder(), "");
  EXPECT_TRUE(frame(f, "  \t").empty());
  EXPECT_EQ(f.takeRemainder(), "") << "whitespace is no message";
}

TEST(MessageFramer, ReportsTheUnfinishedMessageItHolds) {
  MessageFramer f(1 << 20);
  EXPECT_FALSE(f.inMessage());
  EXPECT_TRUE(frame(f, "  ").empty());
  EXPECT_FALSE(f.inMessage()) << "whitespace does not begin a message";
  EXPECT_TRUE(frame(f, "{\"a\": \"").empty());
  EXPECT_TRUE(f.inMessage());
  EXPECT_EQ(f.kept(), 9u);
  EXPECT_GE(f.buffered(), f.kept());
  EXPECT_EQ(frame(f, "b\"}{\"c\""), Messages{"  {\"a\": \"b\"}"});
  EXPECT_TRUE(f.inMessage()) << "the next message has begun";
  EXPECT_EQ(f.kept(), 4u);
  EXPECT_EQ(frame(f, ":1}"), Messages{"{\"c\":1}"});
  EXPECT_FALSE(f.inMessage());
  EXPECT_EQ(f.buffered(), 0u);
}

TEST(MessageFramer, ForgetsALargeMessageOnceItIsHandedOn) {
  MessageFramer f(1 << 22);
  const std::string big = "[\"" + std::string(3 << 20, 'x') + "\"]";
  EXPECT_EQ(frame(f, big).size(), 1u);
  EXPECT_EQ(f.buffered(), 0u);
  std::vector<std::string> out;
  EXPECT_FALSE(f.feed(std::string(5 << 20, ' ') + "x", out)) << "over the limit";
  EXPECT_EQ(f.buffered(), 0u) << "a spent framer holds nothing";
  EXPECT_FALSE(f.inMessage());
}

TEST(MessageFramer, LongStringsAndScalarsFrameAsByteByByte) {
  // The fast path over plain string bytes and scalars must not change where
  // messages end or when the limit is hit.
  const std::string text = "{\"s\": \"" + std::string(5000, 'x') + "\\\"}]" +
                           std::string(3000, 'y') + "\"}" + "  " + std::string(4000, '7') +
                           "\n[\"a\nb\"]\n";
  const Messages expected{text.substr(0, text.find("}  ") + 1), "  " + std::string(4000, '7'),
                          "[\"a", "b\"]"};
  for (std::size_t piece : {1u, 7u, 64u, 4096u, 100000u}) {
    MessageFramer f(1 << 20);
    Messages got;
    for (std::size_t at = 0; at < text.size(); at += piece) {
      const Messages part = frame(f, std::string_view(text).substr(at, piece));
      got.insert(got.end(), part.begin(), part.end());
    }
    EXPECT_TRUE(got == expected) << "pieces of " << piece;  // (too long to print)
  }
  const std::size_t first = expected.front().size();  // the longest message
  for (std::size_t limit : {std::size_t{4999}, std::size_t{5010}, first - 1}) {
    for (std::size_t piece : {1u, 333u, 100000u}) {
      MessageFramer f(limit);
      std::vector<std::string> out;
      bool within = true;
      for (std::size_t at = 0; at < text.size() && within; at += piece)
        within = f.feed(std::string_view(text).substr(at, piece), out);
      EXPECT_FALSE(within) << "limit " << limit << ", pieces of " << piece;
      EXPECT_TRUE(out.empty()) << "limit " << limit << ", pieces of " << piece;
    }
  }
  MessageFramer exact(first);
  std::vector<std::string> out;
  EXPECT_TRUE(exact.feed(text, out)) << "a message of exactly the limit is accepted";
  EXPECT_TRUE(out == expected);
}

TEST(MessageFramer, KeepsALongMessageAcrossManyReads) {
  // Kept in pieces of 64 KiB: the joins must neither lose nor repeat a byte.
  std::string body(300000, ' ');
  for (std::size_t i = 0; i < body.size(); ++i) body[i] = static_cast<char>('a' + i % 26);
  const std::string text = "{\"s\": \"" + body + "\"}\n";
  const std::size_t closing = text.size() - 2;  // the '}' that ends the message
  for (std::size_t piece : {1000u, 65536u, 65537u, 200000u}) {
    MessageFramer f(1 << 20);
    Messages got;
    for (std::size_t at = 0; at < text.size(); at += piece) {
      const Messages part = frame(f, std::string_view(text).substr(at, piece));
      got.insert(got.end(), part.begin(), part.end());
      if (at + piece <= closing) {
        EXPECT_EQ(f.kept(), at + piece) << "pieces of " << piece;
        // The memory held: the kept bytes, plus at most one piece not full yet.
        EXPECT_GE(f.buffered(), f.kept());
        EXPECT_LE(f.buffered(), f.kept() + (256u << 10)) << "pieces of " << piece;
      }
    }
    EXPECT_TRUE(got == Messages{text.substr(0, closing + 1)}) << "pieces of " << piece;
    EXPECT_EQ(f.buffered(), 0u);
  }
  MessageFramer f(1 << 20);
  for (std::size_t at = 0; at < 200000; at += 3000)
    EXPECT_TRUE(
        frame(f, std::string_view(text).substr(at, std::min<std::size_t>(3000, 200000 - at)))
            .empty());
  EXPECT_TRUE(f.takeRemainder() == text.substr(0, 200000));
  EXPECT_EQ(f.buffered(), 0u);
}

TEST(MessageFramer, KnowsAnUnclosedTextFromAScalar) {
  MessageFramer f(1024);
  EXPECT_TRUE(frame(f, "{\"a\": [").empty());
  EXPECT_TRUE(f.inUnclosedText());
  EXPECT_EQ(frame(f, "]}"), Messages{"{\"a\": []}"});
  EXPECT_FALSE(f.inUnclosedText());
  EXPECT_TRUE(frame(f, "12").empty());
  EXPECT_TRUE(f.inMessage());
  EXPECT_FALSE(f.inUnclosedText());
}

}  // namespace
}  // namespace hfts::service
