#include "curvedslicer/export/program_text.hpp"

#include <cctype>
#include <charconv>
#include <cmath>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

std::string_view lineEndingText(LineEnding ending) {
  return ending == LineEnding::Crlf ? std::string_view("\r\n") : std::string_view("\n");
}

void appendFixed(std::string& out, double value, int decimals) {
  if (!std::isfinite(value)) {
    throw InvalidInput("a program value is not a finite number: " + std::to_string(value) +
                       "; check the plan and the cell for NaN or infinite entries");
  }
  if (decimals < 0 || decimals > 17) {
    throw InvalidInput("decimals must be within 0..17: " + std::to_string(decimals) +
                       "; pass a smaller number of decimals");
  }
  char buf[400];
  const auto [end, ec] =
      std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed, decimals);
  if (ec != std::errc()) {
    throw InvalidInput("a program value is too large to print: " + std::to_string(value) +
                       "; check the plan and the cell units");
  }
  const char* begin = buf;
  if (*begin == '-') {
    bool allZero = true;
    for (const char* c = begin + 1; c != end; ++c) {
      if (*c != '0' && *c != '.') {
        allZero = false;
        break;
      }
    }
    if (allZero) ++begin;
  }
  out.append(begin, static_cast<std::size_t>(end - begin));
}

std::string formatFixed(double value, int decimals) {
  std::string s;
  appendFixed(s, value, decimals);
  return s;
}

void appendInt(std::string& out, std::int64_t value) {
  char buf[24];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, static_cast<std::size_t>(end - buf));
}

void ProgramText::line(std::string_view text) {
  text_.append(text);
  endLine();
}

void ProgramText::endLine() {
  text_.append(ending_);
  ++lines_;
}

std::string ProgramText::take() {
  lines_ = 0;
  return std::move(text_);
}

std::vector<IndexRange> splitAtLimit(const std::vector<std::size_t>& costs,
                                     const std::vector<bool>& breakAllowed, std::size_t limit) {
  if (costs.size() != breakAllowed.size()) {
    throw InvalidInput(
        "splitAtLimit: costs and break flags differ in size: " + std::to_string(costs.size()) +
        " vs " + std::to_string(breakAllowed.size()) + "; pass one flag per item");
  }
  for (std::size_t i = 0; i < costs.size(); ++i) {
    if (costs[i] > limit) {
      throw InvalidInput("one program item needs more lines than a job may hold: " +
                         std::to_string(costs[i]) + " > " + std::to_string(limit) +
                         "; raise the maximum lines per job in the cell's export options");
    }
  }
  std::vector<IndexRange> chunks;
  std::size_t begin = 0;
  while (begin < costs.size()) {
    std::size_t sum = 0;
    std::size_t lastBreak = begin;  // last preferred cut after `begin` reached within the limit
    std::size_t i = begin;
    while (i < costs.size() && sum + costs[i] <= limit) {
      if (i > begin && breakAllowed[i]) lastBreak = i;
      sum += costs[i];
      ++i;
    }
    std::size_t end = i;
    if (i < costs.size()) {
      if (breakAllowed[i]) {
        end = i;
      } else if (lastBreak > begin) {
        end = lastBreak;
      }
    }
    chunks.push_back({begin, end});
    begin = end;
  }
  return chunks;
}

std::string makeProgramName(std::string_view base, std::size_t maxLength, bool upperCase) {
  if (maxLength < 1) {
    throw InvalidInput("program name limit must be at least 1 character: " +
                       std::to_string(maxLength) + "; check the cell's export options");
  }
  std::string name;
  for (const char c : base) {
    const unsigned char u = static_cast<unsigned char>(c);
    char out = std::isalnum(u) && u < 128 ? c : '_';
    if (upperCase) out = static_cast<char>(std::toupper(static_cast<unsigned char>(out)));
    name.push_back(out);
  }
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name.front()))) {
    name.insert(name.begin(), 'P');
  }
  if (name.size() > maxLength) name.resize(maxLength);
  return name;
}

std::string makeSubJobName(std::string_view base, std::size_t index, std::size_t count,
                           std::size_t maxLength) {
  const std::size_t width = std::to_string(count).size();
  std::string number = std::to_string(index);
  number.insert(number.begin(), width - std::min(width, number.size()), '0');
  if (number.size() + 1 > maxLength) {
    throw InvalidInput("too many jobs for the job-name limit: " + std::to_string(count) +
                       " jobs with at most " + std::to_string(maxLength) +
                       " characters per name; raise the lines per job or the name limit");
  }
  std::string name(base.substr(0, maxLength - number.size()));
  return name + number;
}

}  // namespace curvedslicer
