// Limits a JSON text must respect before it is parsed: nesting depth and numbers a double can
// hold. nlohmann's parser itself is iterative, but copying, comparing and walking the parsed
// value recurse, so a value nested ~1e5 deep overflows the stack long after parsing; and a
// number like 1e999 makes the parser throw an out_of_range exception that carries no position.
// Checking the text first turns both into an InputError with line and column.
#pragma once
#include <cstddef>
#include <string>

namespace consph {

// Deeper than any scene needs (the bundled ones nest 5 levels), far below what overflows the
// stack of a recursive walk (~1e4-1e5 levels on an 8 MB stack).
inline constexpr int kMaxJsonDepth = 200;

// Throws InputError "WHERE:LINE:COLUMN: ..." at the first array or object nested deeper than
// kMaxJsonDepth, or the first number outside the range of a double. `where` names the text (a
// file, "--set simulation.stopAt"). Malformed JSON is left to the parser.
void checkJsonLimits(const std::string& text, const std::string& where);

// Line and column (1-based) of byte `offset` of `text`.
std::string lineColumn(const std::string& text, std::size_t offset);

}  // namespace consph
