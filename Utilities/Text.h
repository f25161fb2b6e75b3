// Checks on text from scene files that ends up in file names, CSV fields, XML and messages.
#pragma once
#include <string>

namespace consph {

// Valid UTF-8 without control characters: C0 (0x00-0x1f), DEL and C1 (U+0080-U+009F); overlong
// forms and surrogates are invalid.
bool printableUtf8(const std::string& s);

}  // namespace consph
