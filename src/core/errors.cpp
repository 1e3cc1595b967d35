#include <scanplan/core/errors.h>

#include <cctype>
#include <utility>

namespace scanplan {

namespace {

// Whether byte `c` continues a UTF-8 character (10xxxxxx): a cut must not fall before it.
bool continues(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

bool inWord(const std::string& text, std::size_t i) {
  return i < text.size() && std::isalnum(static_cast<unsigned char>(text[i]));
}

// The quote that opens an excerpt at or after `from` (not after a letter or digit, as the
// apostrophe of "the part's" is), and the one that closes it (not before one); npos for
// either when there is none.
std::pair<std::size_t, std::size_t> nextQuoted(const std::string& text, std::size_t from) {
  std::size_t open = text.find('\'', from);
  while (open != std::string::npos && open > 0 && inWord(text, open - 1))
    open = text.find('\'', open + 1);
  if (open == std::string::npos) return {open, open};
  std::size_t close = text.find('\'', open + 1);
  while (close != std::string::npos && inWord(text, close + 1)) close = text.find('\'', close + 1);
  return {open, close};
}

}  // namespace

std::string printable(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return text;
}

std::string briefReason(std::string reason) {
  reason = printable(std::move(reason));
  std::string brief;
  std::size_t at = 0;
  while (at < reason.size()) {
    const auto [open, close] = nextQuoted(reason, at);
    if (close == std::string::npos) break;
    brief.append(reason, at, open + 1 - at);
    if (close - open - 1 <= kQuotedBytes) {
      brief.append(reason, open + 1, close - open - 1);
    } else {
      std::size_t cut = open + 1 + kQuotedBytes - 3;
      while (cut > open + 1 && continues(reason[cut])) --cut;
      brief.append(reason, open + 1, cut - open - 1);
      brief += "...";
    }
    brief += '\'';
    at = close + 1;
  }
  if (at < reason.size()) brief.append(reason, at);
  return brief;
}

}  // namespace scanplan
