#include <cstdio>
int main() { std::puts("xfdem"); return 0; }
