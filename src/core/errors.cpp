#include <scanplan/core/errors.h>

namespace scanplan {

namespace {

// Whether byte `c` continues a UTF-8 character (10xxxxxx): a cut must not fall before it.
bool continues(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

}  // namespace

std::string briefReason(std::string reason) {
  for (char& c : reason)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  std::string brief;
  std::size_t at = 0;
  while (at < reason.size()) {
    const std::size_t open = reason.find('\'', at);
    const std::size_t close = open == std::string::npos ? open : reason.find('\'', open + 1);
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
