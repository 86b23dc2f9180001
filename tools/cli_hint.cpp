#include "cli_hint.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <new>

namespace svo::tools {

namespace {

// Optimal string alignment distance (Damerau-Levenshtein without repeated edits of a substring).
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

std::vector<CLI::App*> commands_of(CLI::App& app) {
  return app.get_subcommands([](CLI::App* sub) { return !sub->get_name().empty(); });
}

std::vector<std::string> option_names(CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* opt : app.get_options()) {
    for (const auto& l : opt->get_lnames()) names.push_back("--" + l);
    for (const auto& s : opt->get_snames()) names.push_back("-" + s);
  }
  return names;
}

bool has_positionals(CLI::App& app) {
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_positional()) return true;
  }
  return false;
}

// "-x", "--word", "--word=value": an option's name; not "-", "--" or a negative number.
bool looks_like_option(const std::string& token) {
  if (token.size() < 2 || token[0] != '-') return false;
  if (token[1] == '-') return token.size() > 2 && std::isalpha(static_cast<unsigned char>(token[2]));
  return std::isalpha(static_cast<unsigned char>(token[1]));
}

std::string with_suggestion(const std::string& what, const std::string& word, const std::vector<std::string>& names) {
  const std::string best = closest_name(word, names);
  return best.empty() ? what : what + " (did you mean '" + best + "'?)";
}

}  // namespace

const CLI::Validator& positive_number() {
  static const CLI::Validator check(
      [](const std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return text + " is not a number";
        return value > 0.0 ? std::string() : text + " is not a positive number";
      },
      "POSITIVE");
  return check;
}

std::string closest_name(const std::string& word, const std::vector<std::string>& names) {
  std::vector<std::string> prefixed;
  for (const auto& n : names) {
    if (n.size() > word.size() && n.compare(0, word.size(), word) == 0) prefixed.push_back(n);
  }
  if (prefixed.size() == 1) return prefixed.front();
  // Distances count the name without its dashes, so that "-" is not free.
  const size_t dashes = word.find_first_not_of('-') == std::string::npos ? 0 : word.find_first_not_of('-');
  const size_t limit = std::max<size_t>(1, (word.size() - dashes) / 3);
  std::string best;
  size_t best_distance = limit + 1;
  for (const auto& n : names) {
    const size_t d = edit_distance(word, n);
    if (d < best_distance) best = n, best_distance = d;
  }
  return best;
}

CommandLineHint command_line_hint(CLI::App& app, int argc, const char* const* argv) {
  CommandLineHint hint{app.get_name().empty() ? "svo" : app.get_name(), ""};
  CLI::App* current = &app;
  bool positional_seen = false;
  for (int i = 1; i < argc; ++i) {
    const std::string token = argv[i];
    if (token == "--") break;
    if (looks_like_option(token)) {
      const std::string name = token.substr(0, token.find('='));
      const CLI::Option* option = current->get_option_no_throw(name);
      if (option == nullptr) {
        hint.message = with_suggestion("unknown option '" + name + "'", name, option_names(*current));
        return hint;
      }
      const size_t eq = token.find('=');
      const bool takes_value = option->get_type_size_min() > 0;
      if (takes_value && option->get_type_name().rfind("FLOAT", 0) == 0) {
        const std::string value = eq != std::string::npos ? token.substr(eq + 1) : i + 1 < argc ? argv[i + 1] : "";
        char* end = nullptr;
        const double v = std::strtod(value.c_str(), &end);
        if (!value.empty() && end && *end == '\0' && !std::isfinite(v)) {
          hint.message = name + " " + value + ": not a finite number";
          hint.non_finite = true;
          return hint;
        }
      }
      if (takes_value && eq == std::string::npos) ++i;  // its value
      continue;
    }
    const auto subs = commands_of(*current);
    auto named = std::find_if(subs.begin(), subs.end(), [&](CLI::App* s) { return s->check_name(token); });
    if (named != subs.end() && !positional_seen) {
      current = *named;
      hint.command += " " + current->get_name();
      continue;
    }
    // A word where a command is expected (and no positional argument can take it).
    if (!subs.empty() && !positional_seen && !has_positionals(*current)) {
      std::vector<std::string> names;
      for (CLI::App* s : subs) names.push_back(s->get_name());
      hint.message = with_suggestion("unknown command '" + token + "'", token, names);
      return hint;
    }
    positional_seen = true;
  }
  if (current->get_require_subcommand_min() > 0 && !positional_seen) {
    std::string names;
    for (CLI::App* s : commands_of(*current)) names += (names.empty() ? "" : ", ") + s->get_name();
    hint.message = "a command is required: " + names;
  }
  return hint;
}

int run_command_line(CLI::App& app, const std::string& version, int argc, char** argv, const int& exit_code) {
  const std::string program = app.get_name();
  app.set_version_flag("--version", version);
  try {
    if (const CommandLineHint pre = command_line_hint(app, argc, argv); pre.non_finite) {
      std::cerr << pre.command << ": " << pre.message << " (see " << pre.command << " --help)\n";
      return 1;
    }
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::CallForVersion&) {
    std::cout << version << "\n";
    return 0;
  } catch (const CLI::ParseError& e) {
    const CommandLineHint hint = command_line_hint(app, argc, argv);
    std::cerr << hint.command << ": " << (hint.message.empty() ? std::string(e.what()) : hint.message) << " (see "
              << hint.command << " --help)\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << program << ": out of host memory (an allocation failed); try a smaller --resolution or image size\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << program << ": " << e.what() << "\n";
    return 1;
  }
  return exit_code;
}

}  // namespace svo::tools
