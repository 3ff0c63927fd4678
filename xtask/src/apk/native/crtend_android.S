// crtend_android.o for the generated no-NDK sysroot (written for dermis; not platform code):
// the 0 entries ending an executable's .preinit_array, .init_array and .fini_array (each
// begun by a -1 in crtbegin_dynamic.c), and a non-executable stack.
        .section .preinit_array,"aw"
        .balign 8
        .quad 0
        .section .init_array,"aw"
        .balign 8
        .quad 0
        .section .fini_array,"aw"
        .balign 8
        .quad 0
        .section .note.GNU-stack,"",%progbits
