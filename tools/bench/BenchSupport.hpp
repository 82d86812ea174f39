#pragma once
// What the files of flexmb_bench share: the clock and the text of its figures (tools/bench/README.md).
#include <chrono>
#include <string>
#include <vector>

namespace flexmb::bench {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start);  // seconds

std::string fmt(const char* format, double v);  // printf of one number
std::string sci(double v, int digits = 2);      // 1.23e-04; "-" when not finite
std::string tolText(double v);                  // 1e-03
std::string secText(double s);                  // seconds, 2-3 significant digits; "-" when not finite
std::string withThousands(long v);              // 12,345
double median(std::vector<double> v);           // NaN when empty
std::string csvQuote(const std::string& s);
std::string mdEscape(std::string s);  // a Markdown table cell: | escaped, one line

}  // namespace flexmb::bench
