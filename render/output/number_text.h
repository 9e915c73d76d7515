// Numbers as text that reads back to the same value: for a double, the shortest such text
// (std::to_chars), so 0.15 is written 0.15 where printf's %.17g writes 0.14999999999999999.
// The numbers of voxfall's tables that read back bit-exact go through here: the trajectory
// CSV, the run summary JSON, an ensemble's paths, evaluation lines and barriers, plot tables.
#pragma once

#include <charconv>
#include <string>

namespace vf {

// Appends `v` (an integer or a floating-point number) to `out`; a NaN or an infinity as "nan",
// "-nan", "inf" or "-inf".
template <class T>
void appendNumber(std::string& out, T v) {
  char text[32];
  out.append(text, std::to_chars(text, text + sizeof text, v).ptr);
}

template <class T>
std::string numberText(T v) {
  std::string out;
  appendNumber(out, v);
  return out;
}

// One CSV row: the numbers separated by commas, ending with a newline.
template <class First, class... Rest>
std::string csvRow(First first, Rest... rest) {
  std::string row;
  appendNumber(row, first);
  ((row += ',', appendNumber(row, rest)), ...);
  row += '\n';
  return row;
}

}  // namespace vf
