#include "tools/bench/BenchSupport.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace flexmb::bench {

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string sci(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*e", digits, v);
  return buf;
}

std::string tolText(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0e", v);
  return buf;
}

std::string secText(double s) {
  if (!std::isfinite(s)) return "-";
  if (s >= 10) return fmt("%.1f", s);
  if (s >= 1) return fmt("%.2f", s);
  if (s >= 0.01) return fmt("%.3f", s);
  return fmt("%.4f", s);
}

std::string withThousands(long v) {
  std::string s = std::to_string(v), out;
  int n = 0;
  for (auto it = s.rbegin(); it != s.rend(); ++it) {
    if (n && n % 3 == 0 && *it != '-') out.push_back(',');
    out.push_back(*it);
    ++n;
  }
  return {out.rbegin(), out.rend()};
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string csvQuote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) {
    if (c == '"')
      o += "\"\"";
    else if (c == '\n')
      o += ' ';
    else
      o += c;
  }
  return o + "\"";
}

std::string mdEscape(std::string s) {
  for (size_t i = 0; (i = s.find('|', i)) != std::string::npos; i += 2) s.replace(i, 1, "\\|");
  for (auto& c : s)
    if (c == '\n') c = ' ';
  return s;
}

}  // namespace flexmb::bench
