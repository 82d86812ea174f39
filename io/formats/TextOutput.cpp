#include "io/formats/TextOutput.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace flexmb::io {

std::string xmlEscape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
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
      case '\'':
        out += "&apos;";
        break;
      default:
        if (c == '\n' || c == '\r' || c == '\t')
          out += ' ';
        else if (static_cast<unsigned char>(c) < 0x20)
          out += '?';
        else
          out += c;
    }
  }
  return out;
}

std::string shortNumber(double v, int digits) {
  if (!std::isfinite(v) || v == 0.0) return "0";
  char buf[64];
  // Round to `digits` significant digits, then print the shortest form of that double.
  const auto r1 = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific, digits - 1);
  double rounded = v;
  std::from_chars(buf, r1.ptr, rounded);
  const auto r2 = std::to_chars(buf, buf + sizeof buf, rounded);
  return std::string(buf, r2.ptr);
}

void writeTextFile(const std::string& path, std::string_view text) {
  const std::string part = path + ".part";
  errno = 0;
  std::ofstream f(part, std::ios::binary | std::ios::trunc);
  if (!f) {
    const std::string why = errno ? std::generic_category().message(errno) : "open failed";
    throw std::runtime_error("cannot open '" + path + "' for writing: " + why);
  }
  f.write(text.data(), static_cast<std::streamsize>(text.size()));
  f.close();
  if (!f) {
    std::remove(part.c_str());
    throw std::runtime_error("error writing '" + path + "' (disk full?)");
  }
  if (std::rename(part.c_str(), path.c_str()) != 0) {
    const std::string why = std::generic_category().message(errno);
    std::remove(part.c_str());
    throw std::runtime_error("cannot rename '" + part + "' to '" + path + "': " + why);
  }
}

}  // namespace flexmb::io
