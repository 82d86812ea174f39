#pragma once
// Locale-independent number text (std::to_chars), one copy for every writer and message: the
// shortest form that reads back to the same double, and printf's %.17g for fixed-width tables.
#include <charconv>
#include <string>

namespace flexmb::text {

// Shortest text that reads back to the same double ("0.1", "1e-05"; a time just below 1 does not
// print as 1).
inline void appendShortest(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}
inline std::string shortest(double v) {
  std::string s;
  appendShortest(s, v);
  return s;
}

// 17 significant digits, like printf's %.17g (the columns of the CSV tables and basis files).
inline void appendG17(std::string& out, double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
  out.append(buf, r.ptr);
}
inline std::string g17(double v) {
  std::string s;
  appendG17(s, v);
  return s;
}

// `digits` significant digits, like printf's %.<digits>g (messages: "about 3.9e-06").
inline std::string significant(double v, int digits) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, digits);
  return std::string(buf, r.ptr);
}

}  // namespace flexmb::text
