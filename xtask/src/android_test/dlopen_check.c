/*
 * `cargo xtask android-test`'s load check (written for dermis): dlopen(RTLD_NOW) the library
 * named by argv[1] on the bionic userland and look up the NativeActivity entry point. RTLD_NOW
 * binds every import at load time, so a symbol missing from the platform libraries fails here.
 * Built with -ffreestanding and the generated sysroot: no headers.
 */

extern void *dlopen(const char *filename, int flags);
extern void *dlsym(void *handle, const char *symbol);
extern char *dlerror(void);
extern int printf(const char *format, ...);

#define RTLD_NOW 2

int main(int argc, char **argv) {
  if (argc != 2) {
    printf("usage: dlopen_check <lib.so>\n");
    return 2;
  }
  void *lib = dlopen(argv[1], RTLD_NOW);
  if (!lib) {
    printf("dlopen(RTLD_NOW) FAILED: %s\n", dlerror());
    return 1;
  }
  void *entry = dlsym(lib, "ANativeActivity_onCreate");
  if (!entry) {
    printf("dlsym(ANativeActivity_onCreate) FAILED: %s\n", dlerror());
    return 1;
  }
  printf("dlopen(RTLD_NOW) OK: %s, ANativeActivity_onCreate at %p\n", argv[1], entry);
  return 0;
}
