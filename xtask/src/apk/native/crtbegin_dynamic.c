/*
 * crtbegin_dynamic.o for the generated no-NDK sysroot (written for dermis; not platform
 * code): the start of a dynamically linked Android executable (test binaries, the dlopen
 * check of `cargo xtask android-test`).
 *
 * The kernel enters `_start` with the stack holding argc, argv, envp and auxv. `_start`
 * passes that address to bionic's `__libc_init`, which runs `main` and `exit`s with its
 * result. The dynamic linker has already run the executable's `.preinit_array` and
 * `.init_array`; `__libc_init` registers `.fini_array` with `__cxa_atexit`. Each array starts
 * with a -1 entry here and ends with the 0 of crtend_android.S: bionic skips -1 and stops at 0
 * (the layout of bionic's own crtbegin.c / crtend.S).
 */

#include "crt_common.h"

typedef struct {
  void (**preinit_array)(void);
  void (**init_array)(void);
  void (**fini_array)(void);
} dermis_structors_array;

extern int main(int argc, char **argv, char **envp);
extern void __libc_init(void *raw_args, void (*onexit)(void),
                        int (*slingshot)(int, char **, char **),
                        dermis_structors_array const *structors) __attribute__((noreturn));

__attribute__((section(".preinit_array"), used)) static void (*dermis_preinit_start)(void) =
    (void (*)(void))-1;
__attribute__((section(".init_array"), used)) static void (*dermis_init_start)(void) =
    (void (*)(void))-1;
__attribute__((section(".fini_array"), used)) static void (*dermis_fini_start)(void) =
    (void (*)(void))-1;

__attribute__((visibility("hidden"), used, noreturn)) void __dermis_start_main(void *raw_args) {
  dermis_structors_array array = {&dermis_preinit_start, &dermis_init_start, &dermis_fini_start};
  __libc_init(raw_args, (void (*)(void))0, &main, &array);
}

__asm__("  .text\n"
        "  .balign 4\n"
        "  .globl _start\n"
        "  .type _start, %function\n"
        "_start:\n"
        "  mov x0, sp\n"
        "  b __dermis_start_main\n"
        "  .size _start, .-_start\n");
