#include "parse_estimate.h"

namespace clothsim {

namespace {
// Peak RSS of `validate` less a tiny scene's, per node counted here: 473-522 B on flow and
// block sequences, maps and keyframe lists; the text itself is held a few times over, and a
// scalar too long for std::string's inline buffer (15 characters) a few times more.
constexpr double kPerNode = 512, kPerByte = 4, kPerLongScalarByte = 4;
constexpr std::int64_t kInlineLength = 15;

// Reads words, not grammar: a word is a run of characters other than blanks and the flow
// indicators `[]{},`, a quoted string being one word whatever it holds.
class NodeCounter {
 public:
  void feed(char c) {
    ++size_.bytes;
    if (quote_) return in_quotes(c);
    if (comment_) {
      if (c == '\n') end_line();
      return;
    }
    if (c == '#' && !in_word_) {  // a comment starts after a blank or at a line's start
      comment_ = true;
      return;
    }
    if (c == '\n') return end_line();
    if (c == ' ' || c == '\t' || c == '\r' || c == ',' || c == ']' || c == '}') return end_word();
    if (c == '[' || c == '{') {
      end_word();
      return flow_collection();
    }
    if (!in_word_) start_word();
    if (word_length_ == 0 && (c == '"' || c == '\'')) quote_ = c;  // a quote opens a word, not inside one
    last_ = c;
    ++word_length_;
  }
  YamlSize finish() {
    end_line();
    return size_;
  }

 private:
  void in_quotes(char c) {
    ++word_length_;
    if (escaped_) escaped_ = false;
    else if (c == '\\' && quote_ == '"') escaped_ = true;
    else if (c == quote_) quote_ = 0;  // '' inside single quotes reopens at once: one word still
  }
  void start_word() {
    in_word_ = true;
    word_length_ = 0;
  }
  // A word is a node, but a lone dash only marks a sequence entry, and a key at the end of a
  // line (or a dash followed by a key or a dash) holds a block collection: one node more.
  void end_word() {
    if (!in_word_) return;
    in_word_ = false;
    if (word_length_ > kInlineLength) size_.long_scalar_bytes += word_length_;
    const bool dash = word_length_ == 1 && last_ == '-';
    const bool key = last_ == ':';
    if (pending_ && (dash || key)) ++size_.nodes;  // "- t: 1" is a map, "- - 0" a sequence
    pending_ = dash || key;
    if (!dash) ++size_.nodes;
  }
  void flow_collection() {
    ++size_.nodes;
    pending_ = false;  // "- [0, 1]", "key: {a: 1}": the collection is the entry's value
  }
  void end_line() {
    end_word();
    comment_ = false;
    if (pending_) ++size_.nodes;  // "cloth:" or "-" alone: a nested block collection (or a null)
    pending_ = false;
  }

  YamlSize size_{1, 0, 0};  // the document's root, a block collection
  bool in_word_ = false, comment_ = false, escaped_ = false, pending_ = false;
  char quote_ = 0, last_ = 0;
  std::int64_t word_length_ = 0;
};
}  // namespace

YamlSize count_yaml_nodes(std::istream& text) {
  NodeCounter counter;
  char buffer[1 << 16];
  while (text.read(buffer, sizeof buffer) || text.gcount() > 0)
    for (std::streamsize i = 0; i < text.gcount(); ++i) counter.feed(buffer[i]);
  return counter.finish();
}

double parse_bytes(const YamlSize& size) {
  return kPerNode * static_cast<double>(size.nodes) + kPerByte * static_cast<double>(size.bytes) +
         kPerLongScalarByte * static_cast<double>(size.long_scalar_bytes);
}

}  // namespace clothsim
