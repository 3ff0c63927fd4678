// crtend_so.o for the generated no-NDK sysroot (written for dermis; not platform code).
// On arm64 nothing has to follow a shared library's objects; the object exists because the
// clang driver links it, and it marks the stack non-executable.
        .section .note.GNU-stack,"",%progbits
