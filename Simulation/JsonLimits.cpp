#include "Simulation/JsonLimits.h"

#include <cmath>
#include <cstdlib>

#include "Utilities/Error.h"

namespace consph {

std::string lineColumn(const std::string& text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

void checkJsonLimits(const std::string& text, const std::string& where) {
  auto fail = [&](std::size_t at, const std::string& why) { throw InputError(where + ":" + lineColumn(text, at) + ": " + why); };
  int depth = 0;
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n; ++i) {
    const char c = text[i];
    if (c == '"') {  // skip the string, escapes included; an unterminated one is the parser's to report
      for (++i; i < n && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) fail(i, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    } else if (c == ']' || c == '}') {
      --depth;
    } else if (c == '-' || (c >= '0' && c <= '9')) {
      std::size_t end = i + 1;
      while (end < n && (std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '.' || text[end] == 'e' ||
                         text[end] == 'E' || text[end] == '+' || text[end] == '-'))
        ++end;
      const std::string token = text.substr(i, end - i);
      if (!std::isfinite(std::strtod(token.c_str(), nullptr)))
        fail(i, "number " + token + " is out of the range of a double");
      i = end - 1;
    }
  }
}

}  // namespace consph
