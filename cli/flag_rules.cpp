#include "flag_rules.hpp"

#include <charconv>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string_view>

#include "nhc/app/run_request.hpp"
#include "nhc/errors.hpp"

namespace nhc::cli::flag_rules {

namespace {

/// The whole text as one number (strtod's syntax, so nan and inf are read and then judged by
/// the rule); false for text that is not one number ("abc", "1x", "").
bool parse_number(const std::string& text, double& value) {
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  while (end != nullptr && std::isspace(static_cast<unsigned char>(*end))) ++end;
  return !text.empty() && end != text.c_str() && *end == '\0';
}

CLI::Validator number_rule(const std::string& description, std::string (*problem)(double)) {
  return CLI::Validator(
      [problem](std::string& text) -> std::string {
        double value = 0;
        if (!parse_number(text, value)) return "'" + text + "' is not a number";
        const std::string why = problem(value);
        return why.empty() ? std::string() : text + " " + why;
      },
      description);
}

}  // namespace

// The rules themselves are the application layer's (nhc/app/run_request.hpp), shared with Python.
CLI::Validator positive() { return number_rule("POSITIVE", app::positive_problem); }
CLI::Validator relative_tolerance() { return number_rule("RTOL", app::relative_tolerance_problem); }
CLI::Validator absolute_tolerance() { return number_rule("ATOL", app::positive_problem); }
CLI::Validator finite() { return number_rule("NUMBER", app::finite_problem); }

CLI::Validator count(long long low, long long high) {
  const std::string range = std::to_string(low) + " to " + std::to_string(high);
  return CLI::Validator(
      [low, high, range](std::string& text) -> std::string {
        long long value = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, value);
        if (text.empty() || ec == std::errc::invalid_argument || ptr != end)
          return "'" + text + "' is not a whole number";
        if (ec == std::errc::result_out_of_range) return text + " " + app::count_problem(high + 1, low, high);
        if (const std::string why = app::count_problem(value, low, high); !why.empty()) return text + " " + why;
        return "";
      },
      "INT in " + range);
}

void refuse_duplicates(const std::vector<std::string>& keys, const std::string& flag, const std::string& what) {
  std::set<std::string> seen;
  for (const std::string& key : keys)
    if (!seen.insert(key).second) throw InputError({flag, 0, 0}, what + " '" + key + "' is given twice");
}

std::string empty_value_message() { return "'' is an empty value: give one, or leave the flag out"; }

std::optional<std::string> empty_inline_value(int argc, const char* const* argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "--") break;
    if (arg.size() > 3 && arg.substr(0, 2) == "--" && arg.find('=') == arg.size() - 1)
      return std::string(arg.substr(0, arg.size() - 1));
  }
  return std::nullopt;
}

void refuse_empty_values(CLI::App& app) {
  const CLI::Validator non_empty(
      [](std::string& text) -> std::string { return text.empty() ? empty_value_message() : ""; }, "");
  for (CLI::App* sub : app.get_subcommands({}))
    for (CLI::Option* option : sub->get_options())
      if (option->get_type_size() > 0 && option->get_name() != "--help") option->check(non_empty);
}

std::vector<double> output_times(double t0, double t_end, long long intervals, const std::string& flags) {
  return app::equally_spaced_output_times(t0, t_end, intervals, flags);
}

}  // namespace nhc::cli::flag_rules
