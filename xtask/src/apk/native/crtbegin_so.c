/*
 * crtbegin_so.o for the generated no-NDK sysroot (written for dermis; not platform code).
 *
 * What a shared library needs before its own objects on Android: `__dso_handle`, `atexit`
 * and the `.note.android.ident` note (crt_common.h), and a destructor running
 * `__cxa_finalize(&__dso_handle)` when the library is unloaded.
 */

#include "crt_common.h"

extern void __cxa_finalize(void *dso);

__attribute__((visibility("hidden"), destructor)) void __dermis_on_dlclose(void) {
  __cxa_finalize(&__dso_handle);
}
