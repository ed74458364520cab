// The sanitizer layer's proof that it can fail: each mode commits one error the layer must catch
// (the ctest entries sanitize.catches_* expect the sanitizer's report). Built only with
// -DDEMBRIDGE_SANITIZE=ON. The volatile indices and values keep the compiler from proving the error
// at compile time.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

namespace {

volatile int past_the_end = 8;
volatile int big = std::numeric_limits<int>::max();

int heap_overflow()
{
  std::vector<double> v(8, 1.0);
  double *p = v.data();
  return static_cast<int>(p[past_the_end]);  // reads one element past an 8-element heap block
}

int signed_overflow()
{
  int a = big;
  return a + 1;  // undefined: int overflow
}

double *volatile held = nullptr;

int leak()
{
  held = new double[64];
  held[0] = 1.0;
  held = nullptr;  // the only pointer is gone
  return 0;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int dembridge_sanitize_probe(const char *mode)
{
  if (!std::strcmp(mode, "heap-overflow")) return heap_overflow();
  if (!std::strcmp(mode, "signed-overflow")) return signed_overflow();
  if (!std::strcmp(mode, "leak")) return leak();
  std::fprintf(stderr, "unknown mode %s\n", mode);
  return 2;
}

#ifndef DEMBRIDGE_SANITIZE_PROBE_LIBRARY
int main(int argc, char **argv)
{
  if (argc != 2) return 2;
  const int r = dembridge_sanitize_probe(argv[1]);
  std::printf("%s: not caught (%d)\n", argv[1], r);
  return 0;
}
#endif
