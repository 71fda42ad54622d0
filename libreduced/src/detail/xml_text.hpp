#pragma once
// Attribute values of the VTK XML files (libreduced's .vtu and the tools' .vtp/.pvd writers).

#include <string>
#include <string_view>

namespace khz::reduced::detail {

/// `text` with the characters XML gives meaning to inside an attribute value escaped.
inline std::string xml_escaped(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace khz::reduced::detail
