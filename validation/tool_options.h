#pragma once
// The validation programs' options after their positional arguments: flags ("--verbose") and
// options with one value ("--grid 6"). --help or -h first prints the usage (exit 0); an unknown
// option or a missing value is reported with the usage (exit 2) instead of being ignored.
#include <cstdio>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>

// The options from argv[first] on, by name (a flag's value is empty), or the exit code to return.
inline std::optional<int> parse_tool_options(const char* tool, const char* usage, int argc, char** argv, int first,
                                             std::initializer_list<const char*> flags,
                                             std::initializer_list<const char*> valued,
                                             std::map<std::string, std::string>& out) {
  const auto in = [](std::initializer_list<const char*> names, const std::string& a) {
    for (const char* n : names)
      if (a == n) return true;
    return false;
  };
  if (argc > 1 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::fputs(usage, stdout);
    return 0;
  }
  if (argc < first) {
    std::fputs(usage, stderr);
    return 2;
  }
  for (int i = first; i < argc; ++i) {
    const std::string a = argv[i];
    if (in(flags, a)) {
      out[a];
    } else if (in(valued, a) && i + 1 < argc) {
      out[a] = argv[++i];
    } else {
      std::fprintf(stderr, "%s: %s: %s\n%s", tool, a.c_str(), in(valued, a) ? "needs a value" : "unknown option", usage);
      return 2;
    }
  }
  return std::nullopt;
}
