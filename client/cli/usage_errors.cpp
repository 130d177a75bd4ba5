#include "cli/usage_errors.hpp"

#include <cstdlib>
#include <vector>

namespace surfdeform::cli {
namespace {

bool IsNumber(const std::string& s) {
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0';
}

bool Takes(CLI::App* app, const std::string& name) {
  return app->get_option_no_throw(name) != nullptr;
}

}  // namespace

std::string ExplainUnexpected(CLI::App& app, int argc, const char* const* argv) {
  const std::vector<CLI::App*> subcommands = app.get_subcommands({});
  CLI::App* given = nullptr;
  int given_at = argc;
  for (int k = 1; k < argc && given == nullptr; ++k) {
    for (CLI::App* sub : subcommands) {
      if (sub->check_name(argv[k])) {
        given = sub;
        given_at = k;
      }
    }
  }
  std::string out;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--") break;
    if (arg.size() < 2 || arg[0] != '-' || IsNumber(arg)) continue;
    const std::string name = arg.substr(0, arg.find('='));
    // Before the subcommand only the program's own options are taken.
    if (Takes(&app, name) || (k > given_at && Takes(given, name))) continue;
    std::vector<std::string> takers;
    for (CLI::App* sub : subcommands) {
      if (Takes(sub, name)) takers.push_back(sub->get_name());
    }
    std::string owners;  // "deform", "deform and batch", "deform, batch and animate"
    for (size_t t = 0; t < takers.size(); ++t) {
      owners += (t == 0 ? "" : t + 1 == takers.size() ? " and " : ", ") + takers[t];
    }
    if (!owners.empty()) {
      out += name + " is an option of " + owners;
      out += k > given_at ? ", not of " + given->get_name() : ": give it after the subcommand";
      out += "\n";
    } else {
      out += "unknown option " + name;
      if (given != nullptr && k > given_at) out += " for " + given->get_name();
      out += "\n";
    }
  }
  return out;
}

}  // namespace surfdeform::cli
