// A program outside the project that uses the installed library through
// find_package(xfdem) and xfdem::kernel.
#include <xfdem/version.hpp>

#include <cstdio>

int main() {
  std::printf("xfdem %s\n", xfdem::version_string());
  return 0;
}
