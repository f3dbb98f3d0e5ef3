// Command-line options bound to a field of an options struct: each option keeps the text it was
// given, and `applyTo` parses the given ones into the struct after CLI11 has parsed the command
// line, so every message has the core's "<what>: <value>; <what to do>" form and every default
// comes from the struct (the help text says "(default X)" with X read from `Options{}`).
// Adding an option of an existing kind is one call in the command's option list.
#pragma once

#include <cstdio>
#include <deque>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "curvedslicer/pipeline/option_parsing.hpp"

namespace curvedslicer::cli {

/// "%g" of a default value, for help texts ("2", "0.05", "30").
inline std::string formatDefault(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", value);
  return buffer;
}
inline std::string formatDefault(std::string_view name) {
  return std::string(name);
}

/// "a (default; what a) or b (what b)": the choices of an enum option for a help text, the one
/// named `defaultName` (toString of the struct's default) marked as the default.
inline std::string describeChoices(const std::vector<std::pair<std::string, std::string>>& choices,
                                   std::string_view defaultName) {
  std::string text;
  for (std::size_t k = 0; k < choices.size(); ++k) {
    if (k > 0) text += k + 1 == choices.size() ? " or " : ", ";
    const auto& [name, what] = choices[k];
    text += name + (name == defaultName ? " (default; " : " (") + what + ")";
  }
  return text;
}

template <typename Options>
class OptionBindings {
 public:
  using Apply = std::function<void(std::string_view text, Options& options)>;

  OptionBindings() = default;
  OptionBindings(const OptionBindings&) = delete;  // CLI11 holds pointers into the slots
  OptionBindings& operator=(const OptionBindings&) = delete;

  /// Adds `name` to `app`; when given on the command line, `apply` parses its text into the
  /// options. @return the CLI11 option (e.g. to mark it required).
  CLI::Option* add(CLI::App& app, const std::string& name, const std::string& help,
                   const std::string& typeName, Apply apply) {
    Slot& slot = slots_.emplace_back();
    slot.apply = std::move(apply);
    slot.option = app.add_option(name, slot.text, help)->type_name(typeName);
    return slot.option;
  }

  /// A length in mm (parseLength) stored in `field`; the help ends with the field's default.
  CLI::Option* addLength(CLI::App& app, const std::string& name, double Options::*field,
                         const std::string& what, const std::string& help) {
    return add(
        app, name, help + " (default " + formatDefault(Options{}.*field) + ").", "MM",
        [field, what](std::string_view text, Options& o) { o.*field = parseLength(text, what); });
  }

  /// An angle in degrees (parseAngle) stored in `field`, as addLength.
  CLI::Option* addAngle(CLI::App& app, const std::string& name, double Options::*field,
                        const std::string& what, const std::string& help) {
    return add(
        app, name, help + " (default " + formatDefault(Options{}.*field) + ").", "DEG",
        [field, what](std::string_view text, Options& o) { o.*field = parseAngle(text, what); });
  }

  /// An angle given in degrees (parseAngle) stored in radians in `field`; the help ends with
  /// the field's default in degrees.
  CLI::Option* addAngleInRadians(CLI::App& app, const std::string& name, double Options::*field,
                                 const std::string& what, const std::string& help) {
    constexpr double kDegree = 3.14159265358979323846 / 180.0;
    return add(app, name, help + " (default " + formatDefault(Options{}.*field / kDegree) + ").",
               "DEG", [field, what](std::string_view text, Options& o) {
                 o.*field = parseAngle(text, what) * kDegree;
               });
  }

  /// A flag that sets the bool `field` to `value` when given (`value` is the opposite of the
  /// field's default, so the help needs no default).
  CLI::Option* addFlag(CLI::App& app, const std::string& name, bool Options::*field, bool value,
                       const std::string& help) {
    Slot& slot = slots_.emplace_back();
    slot.apply = [field, value](std::string_view, Options& o) { o.*field = value; };
    slot.option = app.add_flag(name, help);
    return slot.option;
  }

  /// Parses every option that was given into `options`, in the order they were added.
  /// @throws InvalidInput from the parsers.
  void applyTo(Options& options) const {
    for (const Slot& slot : slots_) {
      if (slot.option != nullptr && slot.option->count() > 0) slot.apply(slot.text, options);
    }
  }

 private:
  struct Slot {
    std::string text;
    CLI::Option* option = nullptr;
    Apply apply;
  };
  std::deque<Slot> slots_;  // stable addresses: CLI11 keeps a pointer to each `text`
};

}  // namespace curvedslicer::cli
