#include <cstdio>
#include "xpbd/xpbd.hpp"
int main() { std::puts("xpbd-demo: placeholder"); return 0; }
