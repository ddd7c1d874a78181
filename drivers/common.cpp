#include "common.hpp"

#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/support/output_folder.hpp>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <system_error>

namespace hemivem::cli {

namespace {

/// The two endings of the interruption message, made before any signal can arrive.
struct InterruptionText {
  std::string kept;  ///< ": DIR keeps its previous outputs\n" (or no outputs were written)
  std::string put;   ///< ": DIR holds this run's outputs\n"
};
InterruptionText interruption_text;

void write_all(const char* text, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(STDERR_FILENO, text, size);
    if (n <= 0) return;
    text += n;
    size -= static_cast<std::size_t>(n);
  }
}

extern "C" void on_interruption(int sig) {
  const char* name = sig == SIGINT ? "hemivem: interrupted by SIGINT" : "hemivem: interrupted by SIGTERM";
  write_all(name, std::strlen(name));
  const std::string& end = committed_transactions() > 0 ? interruption_text.put : interruption_text.kept;
  write_all(end.data(), end.size());
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

}  // namespace

void say_what_an_interruption_keeps(const std::filesystem::path& dir) {
  if (!reporting_process()) return;
  interruption_text.kept = ": " + previous_outputs_kept(dir) + "\n";
  interruption_text.put = ": " + dir.string() + " holds this run's outputs\n";
  struct sigaction action {};
  action.sa_handler = on_interruption;
  sigemptyset(&action.sa_mask);
  for (int sig : {SIGINT, SIGTERM}) ::sigaction(sig, &action, nullptr);
}

std::string toml_string(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

std::string figure_format_override(const std::string& formats) {
  std::string list;
  std::stringstream names(formats);
  for (std::string name; std::getline(names, name, ',');) list += (list.empty() ? "" : ", ") + toml_string(name);
  return "output.figure_format=[" + list + "]";
}

bool reporting_process() { return launched_processes().rank == 0 && factorization_process_rank() == 0; }

std::vector<int> parse_sizes(const std::string& text, const std::string& flag) {
  std::vector<int> sizes;
  std::size_t start = 0;
  for (int place = 1;; ++place) {
    const std::size_t comma = text.find(',', start);
    std::string entry = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    entry.erase(0, entry.find_first_not_of(" \t"));
    entry.erase(entry.find_last_not_of(" \t") + 1);
    const std::string where = "entry " + std::to_string(place) + " of '" + text + "'";
    if (entry.empty())
      throw InputError(where + " is empty: give the sizes separated by single commas, e.g. 4,8,16", flag);
    long long v = 0;
    const auto [end, ec] = std::from_chars(entry.data(), entry.data() + entry.size(), v);
    if (ec == std::errc::invalid_argument || end != entry.data() + entry.size())
      throw InputError(where + ", '" + entry + "', is not an integer", flag);
    if (ec == std::errc::result_out_of_range || v < 1 || v > 10000000)
      throw InputError(where + ", " + entry + ", is not in [1, 10000000]", flag);
    sizes.push_back(static_cast<int>(v));
    if (comma == std::string::npos) return sizes;
    start = comma + 1;
  }
}

}  // namespace hemivem::cli
