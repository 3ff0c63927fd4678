/*
 * What every crtbegin object of the generated no-NDK sysroot carries (written for dermis; not
 * platform code), included by crtbegin_so.c (shared libraries) and crtbegin_dynamic.c
 * (executables):
 *  - `__dso_handle`, identifying this module to `__cxa_atexit` / `__cxa_finalize`;
 *  - `atexit`, which must register against this module (bionic's libc has no `atexit`
 *    export for NDK code: the NDK gets it from crtbegin);
 *  - the `.note.android.ident` note carrying the minimum API level.
 *
 * Built with -ffreestanding: no headers are needed. DERMIS_API_LEVEL is passed with -D.
 */

extern int __cxa_atexit(void (*func)(void *), void *arg, void *dso);

__attribute__((visibility("hidden"))) void *__dso_handle = &__dso_handle;

__attribute__((visibility("hidden"))) int atexit(void (*func)(void)) {
  return __cxa_atexit((void (*)(void *))func, (void *)0, &__dso_handle);
}

#define DERMIS_STR2(x) #x
#define DERMIS_STR(x) DERMIS_STR2(x)

/* ELF note: namesz, descsz, type 1, "Android\0", then int32 api level, char ndk_version[64],
 * char ndk_build_number[64] (the layout bionic's crtbrand.S uses). */
__asm__(
    "  .section .note.android.ident,\"a\",%note\n"
    "  .balign 4\n"
    "  .type __dermis_android_ident, %object\n"
    "__dermis_android_ident:\n"
    "  .long 2f-1f\n"
    "  .long 3f-2f\n"
    "  .long 1\n"
    "1:.ascii \"Android\\0\"\n"
    "2:.long " DERMIS_STR(DERMIS_API_LEVEL) "\n"
    "  .ascii \"dermis-no-ndk\"\n"
    "  .fill 64-13, 1, 0\n"
    "  .ascii \"0\"\n"
    "  .fill 64-1, 1, 0\n"
    "3:\n"
    "  .size __dermis_android_ident, .-__dermis_android_ident\n"
    "  .text\n");
