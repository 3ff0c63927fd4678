/*
 * glibc -> bionic shims for Debian's arm64 LLVM libunwind.a (written for dermis).
 *
 * Debian builds libunwind against glibc, so its objects reference three glibc-only entry
 * points (from errno, assert() and _FORTIFY_SOURCE's fprintf). Bionic has equivalents; these
 * hidden definitions forward to them. They go into the sysroot's libunwind.a and are never
 * exported from the app's library.
 */

typedef struct __sFILE FILE;
typedef __builtin_va_list va_list;

extern int *__errno(void);
extern void __assert2(const char *file, int line, const char *function,
                      const char *expression) __attribute__((noreturn));
extern int vfprintf(FILE *stream, const char *format, va_list ap);

__attribute__((visibility("hidden"))) int *__errno_location(void) { return __errno(); }

__attribute__((visibility("hidden"), noreturn)) void
__assert_fail(const char *expression, const char *file, unsigned int line,
              const char *function) {
  __assert2(file, (int)line, function, expression);
}

__attribute__((visibility("hidden"))) int __fprintf_chk(FILE *stream, int flag,
                                                        const char *format, ...) {
  (void)flag;
  va_list ap;
  __builtin_va_start(ap, format);
  int r = vfprintf(stream, format, ap);
  __builtin_va_end(ap);
  return r;
}
