// The hemivem command.
#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"hemivem: virtual element method for contact problems with nonmonotone laws"};
  app.set_version_flag("--version", std::string("hemivem ") + HEMIVEM_VERSION);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
