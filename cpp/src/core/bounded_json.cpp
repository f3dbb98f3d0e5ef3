#include "core/bounded_json.hpp"

#include <fstream>
#include <optional>
#include <system_error>
#include <utility>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace {

using Json = nlohmann::json;

/// Longest library message kept (a number token can be as long as the file).
constexpr std::size_t kMaxDetail = 200;

struct TextLocation {
  std::size_t line = 1;    ///< 1-based
  std::size_t column = 0;  ///< bytes read on the line (1-based column of the last byte read)
};

std::string where(const TextLocation& at) {
  return "line " + std::to_string(at.line) + ", column " + std::to_string(at.column);
}

/// The first byte where arrays and objects nest deeper than `maxDepth`, outside strings; none if
/// the text never does. Brackets inside strings (with escapes) do not count.
std::optional<TextLocation> findExcessiveNesting(std::string_view text, int maxDepth) {
  TextLocation at;
  int depth = 0;
  bool inString = false;
  bool escaped = false;
  for (const char c : text) {
    ++at.column;
    if (c == '\n') {
      ++at.line;
      at.column = 0;
    }
    if (inString) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > maxDepth) return at;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::nullopt;
}

/// The library's message without its "[json.exception.xxx.nnn] " tag, at most kMaxDetail long.
std::string libraryDetail(const nlohmann::detail::exception& e) {
  std::string what = e.what();
  const auto tag = what.find("] ");
  if (what.rfind("[json.exception.", 0) == 0 && tag != std::string::npos) {
    what = what.substr(tag + 2);
  }
  if (what.size() > kMaxDetail) what = what.substr(0, kMaxDetail) + "...";
  return what;
}

/// Builds the document through the library's DOM builder but keeps the first error with its
/// position instead of throwing (the library's number-overflow error carries no position).
class LocatingSax : public nlohmann::json_sax<Json> {
 public:
  explicit LocatingSax(Json& result) : dom_(result, true) {}

  bool null() override { return dom_.null(); }
  bool boolean(bool v) override { return dom_.boolean(v); }
  bool number_integer(number_integer_t v) override { return dom_.number_integer(v); }
  bool number_unsigned(number_unsigned_t v) override { return dom_.number_unsigned(v); }
  bool number_float(number_float_t v, const string_t& s) override {
    return dom_.number_float(v, s);
  }
  bool string(string_t& v) override { return dom_.string(v); }
  bool binary(binary_t& v) override { return dom_.binary(v); }
  bool start_object(std::size_t n) override { return dom_.start_object(n); }
  bool key(string_t& v) override { return dom_.key(v); }
  bool end_object() override { return dom_.end_object(); }
  bool start_array(std::size_t n) override { return dom_.start_array(n); }
  bool end_array() override { return dom_.end_array(); }
  bool parse_error(std::size_t position, const std::string& /*lastToken*/,
                   const nlohmann::detail::exception& e) override {
    problem_ = libraryDetail(e);
    position_ = position;
    return false;
  }

  const std::string& problem() const { return problem_; }
  std::size_t position() const { return position_; }

 private:
  nlohmann::detail::json_sax_dom_parser<Json> dom_;
  std::string problem_;
  std::size_t position_ = 0;  ///< bytes read when the error was found
};

/// Line and column of byte `offset` (the library counts them too, but only reports them in the
/// text of syntax errors).
TextLocation locate(std::string_view text, std::size_t offset) {
  TextLocation at;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    ++at.column;
    if (text[i] == '\n') {
      ++at.line;
      at.column = 0;
    }
  }
  return at;
}

void appendAbbreviated(std::string& out, const Json& value, std::size_t limit) {
  if (out.size() > limit) return;
  if (value.is_array()) {
    out += '[';
    for (std::size_t i = 0; i < value.size() && out.size() <= limit; ++i) {
      if (i) out += ',';
      appendAbbreviated(out, value[i], limit);
    }
    out += ']';
  } else if (value.is_object()) {
    out += '{';
    bool first = true;
    for (auto it = value.begin(); it != value.end() && out.size() <= limit; ++it) {
      if (!first) out += ',';
      first = false;
      appendAbbreviated(out, Json(it.key().substr(0, limit + 1)), limit);
      out += ':';
      appendAbbreviated(out, it.value(), limit);
    }
    out += '}';
  } else if (value.is_string()) {
    const Json cut(value.get_ref<const std::string&>().substr(0, limit + 1));
    out += cut.dump(-1, ' ', false, Json::error_handler_t::replace);
  } else {
    out += value.dump(-1, ' ', false, Json::error_handler_t::replace);
  }
}

}  // namespace

Json parseBoundedJson(std::string_view text, std::string_view lead, std::string_view hint,
                      int maxDepth) {
  const auto fail = [&](const std::string& problem) {
    throw InvalidInput(std::string(lead) + ": " + problem + "; " + std::string(hint));
  };
  if (const auto deep = findExcessiveNesting(text, maxDepth)) {
    fail("arrays and objects nest deeper than " + std::to_string(maxDepth) + " levels at " +
         where(*deep));
  }
  Json result;
  LocatingSax sax(result);
  bool ok = false;
  try {
    ok = Json::sax_parse(text.begin(), text.end(), &sax);
  } catch (const Json::exception& e) {
    fail(libraryDetail(e));
  }
  if (!ok) {
    const std::string& problem = sax.problem();
    // Syntax errors already name line and column; other library errors (number overflow) do not.
    if (problem.find(" at line ") != std::string::npos) fail(problem);
    fail(problem + " at " + where(locate(text, sax.position())));
  }
  return result;
}

std::string abbreviateJson(const Json& value, std::size_t maxChars) {
  std::string out;
  appendAbbreviated(out, value, maxChars);
  if (out.size() > maxChars) {
    out.resize(maxChars);
    out += "...";
  }
  return out;
}

std::string readInputFile(const std::filesystem::path& path, std::string_view what,
                          std::uintmax_t maxBytes) {
  namespace fs = std::filesystem;
  const std::string name = std::string(what) + " '" + path.string() + "'";
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);  // follows links; never opens the file
  if (ec || !fs::exists(status)) {
    throw IoError("cannot open the " + name + ": it does not exist; check the path");
  }
  const auto refuse = [&](const char* kind) {
    throw InvalidInput("the " + name + " is " + kind + ", not a regular file; pass the " +
                       std::string(what) + " itself");
  };
  if (fs::is_directory(status)) refuse("a folder");
  if (fs::is_fifo(status)) refuse("a FIFO (named pipe)");
  if (fs::is_character_file(status) || fs::is_block_file(status)) refuse("a device");
  if (fs::is_socket(status)) refuse("a socket");
  if (!fs::is_regular_file(status)) refuse("not a file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw IoError("cannot read the size of the " + name + ": " + ec.message());
  if (size > maxBytes) {
    throw InvalidInput("the " + name + " has " + std::to_string(size) + " bytes, more than the " +
                       std::to_string(maxBytes >> 20) + " MiB a " + std::string(what) +
                       " may have; check that it is the right file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open the " + name + "; check its permissions");
  std::string text(static_cast<std::size_t>(size), '\0');
  if (size > 0 && !in.read(text.data(), static_cast<std::streamsize>(size))) {
    throw IoError("reading the " + name + " failed; check the file");
  }
  return text;
}

}  // namespace curvedslicer
