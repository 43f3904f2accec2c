/* A minimal FMI 2.0 co-simulation importer for scripts/old-glibc.sh: loads one FMU
 * binary with dlopen, runs StickSlipBeam on the paper scene and prints the tip
 * deflection as exact hexadecimal floats, so runs under two C libraries can be compared
 * bit for bit. Built with `zig cc` for glibc 2.17, so it runs under any glibc the FMU
 * is meant to load on.
 *
 * Usage: driver LIBRARY GUID RESOURCE_URI TIP_VR STEPS [VR=VALUE ...]
 * (VR=VALUE: Integer parameters (the choices are Integer codes) set in initialization mode.)
 * Exit status: 0 ran; 2 the library did not load (the loader's reason on stderr);
 * 3 an FMI call failed. */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

typedef void *Component;
typedef struct {
    void (*logger)(void *, const char *, int, const char *, const char *, ...);
    void *(*allocate_memory)(size_t, size_t);
    void (*free_memory)(void *);
    void (*step_finished)(void *, int);
    void *environment;
} Callbacks;

static void logger(void *env, const char *instance, int status, const char *category,
                   const char *message, ...) {
    va_list args;
    (void)env;
    va_start(args, message);
    fprintf(stderr, "[%s %d %s] ", instance, status, category);
    vfprintf(stderr, message, args);
    fputc('\n', stderr);
    va_end(args);
}

static void *symbol(void *library, const char *name) {
    void *f = dlsym(library, name);
    if (!f) {
        fprintf(stderr, "missing %s\n", name);
        exit(3);
    }
    return f;
}

#define CHECK(call)                                              \
    do {                                                         \
        int status_ = (call);                                    \
        if (status_ > 1) {                                       \
            fprintf(stderr, "%s returned %d\n", #call, status_); \
            return 3;                                            \
        }                                                        \
    } while (0)

int main(int argc, char **argv) {
    if (argc < 6) {
        fprintf(stderr, "usage: %s LIBRARY GUID RESOURCE_URI TIP_VR STEPS [VR=VALUE ...]\n", argv[0]);
        return 1;
    }
    void *library = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        return 2;
    }
    const char *(*get_version)(void) = symbol(library, "fmi2GetVersion");
    Component (*instantiate)(const char *, int, const char *, const char *, const Callbacks *, int, int) =
        symbol(library, "fmi2Instantiate");
    int (*setup)(Component, int, double, double, int, double) = symbol(library, "fmi2SetupExperiment");
    int (*enter_init)(Component) = symbol(library, "fmi2EnterInitializationMode");
    int (*exit_init)(Component) = symbol(library, "fmi2ExitInitializationMode");
    int (*set_integer)(Component, const unsigned *, size_t, const int *) = symbol(library, "fmi2SetInteger");
    int (*get_real)(Component, const unsigned *, size_t, double *) = symbol(library, "fmi2GetReal");
    int (*do_step)(Component, double, double, int) = symbol(library, "fmi2DoStep");
    int (*terminate)(Component) = symbol(library, "fmi2Terminate");
    void (*free_instance)(Component) = symbol(library, "fmi2FreeInstance");

    Callbacks callbacks = {logger, calloc, free, NULL, NULL};
    unsigned tip_vr = (unsigned)atoi(argv[4]);
    int steps = atoi(argv[5]);
    const double h = 1e-3;

    printf("fmi2GetVersion: %s\n", get_version());
    Component c = instantiate("old-glibc", 1 /* fmi2CoSimulation */, argv[2], argv[3], &callbacks, 0, 0);
    if (!c) {
        fprintf(stderr, "fmi2Instantiate failed\n");
        return 3;
    }
    CHECK(setup(c, 0, 0.0, 0.0, 1, steps * h));
    CHECK(enter_init(c));
    for (int a = 6; a < argc; ++a) {
        unsigned vr;
        int value;
        if (sscanf(argv[a], "%u=%d", &vr, &value) != 2) {
            fprintf(stderr, "not VR=VALUE: %s\n", argv[a]);
            return 1;
        }
        CHECK(set_integer(c, &vr, 1, &value));
    }
    CHECK(exit_init(c));
    double t = 0.0, tip = 0.0, peak = 0.0;
    for (int k = 1; k <= steps; ++k) {
        CHECK(do_step(c, t, h, 1));
        t += h;
        CHECK(get_real(c, &tip_vr, 1, &tip));
        if (tip > peak) peak = tip;
        if (k % 100 == 0) printf("t = %.3f s: tip_deflection = %a m\n", t, tip);
    }
    printf("peak tip_deflection = %a m (%.4f mm)\n", peak, peak * 1e3);
    CHECK(terminate(c));
    free_instance(c);
    return 0;
}
