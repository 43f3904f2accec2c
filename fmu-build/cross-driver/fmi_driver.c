/*
 * fmi_driver: a minimal FMI 2.0 / 3.0 co-simulation importer for the cross-platform
 * tests (python-checks/tests/test_cross_platform.py). It is compiled natively, with
 * mingw for Windows (run under Wine) and for aarch64 Linux (run under qemu), loads one
 * FMU binary, follows a plan read from stdin and prints every requested output as the
 * hex bits of its value, so that outputs from different platforms compare bit for bit
 * as text.
 *
 *   fmi_driver <2|3> <binary> <resources folder> <GUID or instantiation token> < plan
 *
 * The resources folder is a path in the platform's own form (Z:/... under Wine); the
 * driver makes the FMI 2.0 file URI from it. Plan lines (numbers: decimal integers, or a
 * double as 0x + the 16 hex digits of its bits, so that no C library's decimal parser
 * decides an input):
 *   real VR BITS | int VR N | bool VR 0|1 | string VR TEXT    set a variable
 *   output real|int|bool VR                                  print this after each step
 *   init START STOP                                          initialisation, stop time
 *   step H N                                                 N steps of H, print each
 * Lines after init set inputs for the steps that follow: a plan with set lines between
 * its step lines drives a history (NeuralFriction's laws with state integrate their state
 * over each step with the inputs held, python-checks' cross_cases.HISTORY).
 * Each step prints: "t=<bits of the time after the step> <output>..." with a real as
 * its 16 hex digits and an int or bool as a decimal.
 *
 * Compile with -ffp-contract=off: the only arithmetic here (t += h) must round the same
 * on every platform (aarch64 gcc fuses a*b+c by default).
 *
 * The FMI types are declared here from the standards' function signatures (FMI 2.0.4
 * sec. 2.1 and 4.2, FMI 3.0 sec. 2.3 and 4.2), only those this driver calls.
 */
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
#include <windows.h>
static void *open_library(const char *path) { return (void *)LoadLibraryA(path); }
static void *symbol(void *library, const char *name) {
    return (void *)GetProcAddress((HMODULE)library, name);
}
static const char *load_error(void) { return "LoadLibraryA failed"; }
#else
#include <dlfcn.h>
static void *open_library(const char *path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static void *symbol(void *library, const char *name) { return dlsym(library, name); }
static const char *load_error(void) { return dlerror(); }
#endif

#define MAX_OUTPUTS 256
#define MAX_LINE 4096

typedef unsigned int vr_t;
enum kind { KIND_REAL, KIND_INT, KIND_BOOL };
struct output { enum kind kind; vr_t vr; };

/* ---- FMI 2.0 ---- */
typedef void (*fmi2Logger)(void *, const char *, int, const char *, const char *, ...);
typedef struct {
    fmi2Logger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, int);
    void *componentEnvironment;
} fmi2Callbacks;
typedef void *(*fmi2Instantiate_t)(const char *, int, const char *, const char *,
                                   const fmi2Callbacks *, int, int);
typedef int (*fmi2Setup_t)(void *, int, double, double, int, double);
typedef int (*fmi2Plain_t)(void *);
typedef void (*fmi2Free_t)(void *);
typedef int (*fmi2SetReal_t)(void *, const vr_t *, size_t, const double *);
typedef int (*fmi2SetInt_t)(void *, const vr_t *, size_t, const int *);
typedef int (*fmi2SetString_t)(void *, const vr_t *, size_t, const char *const *);
typedef int (*fmi2GetReal_t)(void *, const vr_t *, size_t, double *);
typedef int (*fmi2GetInt_t)(void *, const vr_t *, size_t, int *);
typedef int (*fmi2DoStep_t)(void *, double, double, int);

/* ---- FMI 3.0 ---- */
typedef void (*fmi3Log)(void *, int, const char *, const char *);
typedef void *(*fmi3Instantiate_t)(const char *, const char *, const char *, bool, bool, bool,
                                   bool, const vr_t *, size_t, void *, fmi3Log, void *);
typedef int (*fmi3Enter_t)(void *, bool, double, double, bool, double);
typedef int (*fmi3Plain_t)(void *);
typedef void (*fmi3Free_t)(void *);
typedef int (*fmi3SetF64_t)(void *, const vr_t *, size_t, const double *, size_t);
typedef int (*fmi3SetI32_t)(void *, const vr_t *, size_t, const int32_t *, size_t);
typedef int (*fmi3SetBool_t)(void *, const vr_t *, size_t, const bool *, size_t);
typedef int (*fmi3SetString_t)(void *, const vr_t *, size_t, const char *const *, size_t);
typedef int (*fmi3GetF64_t)(void *, const vr_t *, size_t, double *, size_t);
typedef int (*fmi3GetI32_t)(void *, const vr_t *, size_t, int32_t *, size_t);
typedef int (*fmi3GetBool_t)(void *, const vr_t *, size_t, bool *, size_t);
typedef int (*fmi3DoStep_t)(void *, double, double, bool, bool *, bool *, bool *, double *);

static void fail(const char *what) {
    fprintf(stderr, "fmi_driver: %s\n", what);
    exit(2);
}

static void check(int status, const char *call) {
    /* fmi2OK and fmi3OK are 0, Warning 1; Discard, Error and Fatal end the run. */
    if (status > 1) {
        fprintf(stderr, "fmi_driver: %s returned status %d\n", call, status);
        exit(3);
    }
}

static void *need(void *library, const char *name) {
    void *f = symbol(library, name);
    if (!f) {
        fprintf(stderr, "fmi_driver: %s is not exported\n", name);
        exit(2);
    }
    return f;
}

static void log_fmi2(void *env, const char *instance, int status, const char *category,
                 const char *format, ...) {
    va_list args;
    (void)env;
    fprintf(stderr, "[%s %d %s] ", instance, status, category);
    va_start(args, format);
    vfprintf(stderr, format, args);
    va_end(args);
    fputc('\n', stderr);
}

static void log_fmi3(void *env, int status, const char *category, const char *message) {
    (void)env;
    fprintf(stderr, "[%d %s] %s\n", status, category, message);
}

static double bits_to_double(const char *text) {
    uint64_t bits = strtoull(text, NULL, 16);
    double value;
    memcpy(&value, &bits, sizeof value);
    return value;
}

static void print_double(double value) {
    uint64_t bits;
    memcpy(&bits, &value, sizeof bits);
    printf("%08lx%08lx", (unsigned long)(bits >> 32), (unsigned long)(bits & 0xffffffffu));
}

/* One loaded FMU of either version, behind the same small interface. */
struct fmu {
    int version;
    void *instance;
    void *lib;
};

static void set_real(struct fmu *f, vr_t vr, double v) {
    if (f->version == 2)
        check(((fmi2SetReal_t)need(f->lib, "fmi2SetReal"))(f->instance, &vr, 1, &v), "fmi2SetReal");
    else
        check(((fmi3SetF64_t)need(f->lib, "fmi3SetFloat64"))(f->instance, &vr, 1, &v, 1),
              "fmi3SetFloat64");
}

static void set_int(struct fmu *f, vr_t vr, int v) {
    if (f->version == 2) {
        check(((fmi2SetInt_t)need(f->lib, "fmi2SetInteger"))(f->instance, &vr, 1, &v),
              "fmi2SetInteger");
    } else {
        int32_t w = v;
        check(((fmi3SetI32_t)need(f->lib, "fmi3SetInt32"))(f->instance, &vr, 1, &w, 1),
              "fmi3SetInt32");
    }
}

static void set_bool(struct fmu *f, vr_t vr, int v) {
    if (f->version == 2) {
        check(((fmi2SetInt_t)need(f->lib, "fmi2SetBoolean"))(f->instance, &vr, 1, &v),
              "fmi2SetBoolean");
    } else {
        bool w = v != 0;
        check(((fmi3SetBool_t)need(f->lib, "fmi3SetBoolean"))(f->instance, &vr, 1, &w, 1),
              "fmi3SetBoolean");
    }
}

static void set_string(struct fmu *f, vr_t vr, const char *v) {
    if (f->version == 2)
        check(((fmi2SetString_t)need(f->lib, "fmi2SetString"))(f->instance, &vr, 1, &v),
              "fmi2SetString");
    else
        check(((fmi3SetString_t)need(f->lib, "fmi3SetString"))(f->instance, &vr, 1, &v, 1),
              "fmi3SetString");
}

static void print_output(struct fmu *f, const struct output *o) {
    putchar(' ');
    if (o->kind == KIND_REAL) {
        double v;
        if (f->version == 2)
            check(((fmi2GetReal_t)need(f->lib, "fmi2GetReal"))(f->instance, &o->vr, 1, &v),
                  "fmi2GetReal");
        else
            check(((fmi3GetF64_t)need(f->lib, "fmi3GetFloat64"))(f->instance, &o->vr, 1, &v, 1),
                  "fmi3GetFloat64");
        print_double(v);
    } else if (f->version == 2) {
        int v;
        const char *name = o->kind == KIND_INT ? "fmi2GetInteger" : "fmi2GetBoolean";
        check(((fmi2GetInt_t)need(f->lib, name))(f->instance, &o->vr, 1, &v), name);
        printf("%d", v);
    } else if (o->kind == KIND_INT) {
        int32_t v;
        check(((fmi3GetI32_t)need(f->lib, "fmi3GetInt32"))(f->instance, &o->vr, 1, &v, 1),
              "fmi3GetInt32");
        printf("%d", (int)v);
    } else {
        bool v;
        check(((fmi3GetBool_t)need(f->lib, "fmi3GetBoolean"))(f->instance, &o->vr, 1, &v, 1),
              "fmi3GetBoolean");
        printf("%d", v ? 1 : 0);
    }
}

static void instantiate(struct fmu *f, const char *resources, const char *token) {
    static fmi2Callbacks callbacks = {(fmi2Logger)log_fmi2, calloc, free, NULL, NULL};
    if (f->version == 2) {
        char uri[MAX_LINE];
        /* file:///<path>: a Unix path starts with '/', a Windows one with its drive. */
        snprintf(uri, sizeof uri, "file://%s%s", resources[0] == '/' ? "" : "/", resources);
        f->instance = ((fmi2Instantiate_t)need(f->lib, "fmi2Instantiate"))(
            "driver", 1 /* fmi2CoSimulation */, token, uri, &callbacks, 0, 0);
    } else {
        f->instance = ((fmi3Instantiate_t)need(f->lib, "fmi3InstantiateCoSimulation"))(
            "driver", token, resources, false, false, false, false, NULL, 0, NULL, log_fmi3, NULL);
    }
    if (!f->instance)
        fail("instantiation failed");
}

static void initialize(struct fmu *f, double start, double stop) {
    if (f->version == 2) {
        check(((fmi2Setup_t)need(f->lib, "fmi2SetupExperiment"))(f->instance, 0, 0.0, start, 1,
                                                                  stop),
              "fmi2SetupExperiment");
        check(((fmi2Plain_t)need(f->lib, "fmi2EnterInitializationMode"))(f->instance),
              "fmi2EnterInitializationMode");
        check(((fmi2Plain_t)need(f->lib, "fmi2ExitInitializationMode"))(f->instance),
              "fmi2ExitInitializationMode");
    } else {
        check(((fmi3Enter_t)need(f->lib, "fmi3EnterInitializationMode"))(f->instance, false, 0.0,
                                                                         start, true, stop),
              "fmi3EnterInitializationMode");
        check(((fmi3Plain_t)need(f->lib, "fmi3ExitInitializationMode"))(f->instance),
              "fmi3ExitInitializationMode");
    }
}

static void do_step(struct fmu *f, double t, double h) {
    if (f->version == 2) {
        check(((fmi2DoStep_t)need(f->lib, "fmi2DoStep"))(f->instance, t, h, 1), "fmi2DoStep");
    } else {
        bool event = false, terminate = false, early = false;
        double last = t;
        check(((fmi3DoStep_t)need(f->lib, "fmi3DoStep"))(f->instance, t, h, true, &event,
                                                         &terminate, &early, &last),
              "fmi3DoStep");
        if (terminate || early)
            fail("fmi3DoStep asked to terminate or returned early");
    }
}

static void finish(struct fmu *f) {
    const char *terminate = f->version == 2 ? "fmi2Terminate" : "fmi3Terminate";
    const char *free_instance = f->version == 2 ? "fmi2FreeInstance" : "fmi3FreeInstance";
    check(((fmi2Plain_t)need(f->lib, terminate))(f->instance), terminate);
    ((fmi2Free_t)need(f->lib, free_instance))(f->instance);
}

int main(int argc, char **argv) {
    struct fmu f = {0, NULL, NULL};
    struct output outputs[MAX_OUTPUTS];
    size_t n_outputs = 0;
    char line[MAX_LINE];
    double t = 0.0;
    if (argc != 5 || (strcmp(argv[1], "2") != 0 && strcmp(argv[1], "3") != 0))
        fail("usage: fmi_driver <2|3> <binary> <resources folder> <token> < plan");
    f.version = argv[1][0] - '0';
    f.lib = open_library(argv[2]);
    if (!f.lib) {
        fprintf(stderr, "fmi_driver: cannot load %s: %s\n", argv[2], load_error());
        return 2;
    }
    instantiate(&f, argv[3], argv[4]);
    while (fgets(line, sizeof line, stdin)) {
        char command[16], a[MAX_LINE], b[MAX_LINE];
        unsigned vr;
        line[strcspn(line, "\r\n")] = '\0';
        if (sscanf(line, "%15s", command) != 1)
            continue;
        if (strcmp(command, "real") == 0 && sscanf(line, "real %u %s", &vr, a) == 2) {
            set_real(&f, vr, bits_to_double(a));
        } else if (strcmp(command, "int") == 0 && sscanf(line, "int %u %s", &vr, a) == 2) {
            set_int(&f, vr, atoi(a));
        } else if (strcmp(command, "bool") == 0 && sscanf(line, "bool %u %s", &vr, a) == 2) {
            set_bool(&f, vr, atoi(a));
        } else if (strcmp(command, "string") == 0 && sscanf(line, "string %u %s", &vr, a) == 2) {
            set_string(&f, vr, a);
        } else if (strcmp(command, "output") == 0 &&
                   sscanf(line, "output %s %u", a, &vr) == 2) {
            if (n_outputs == MAX_OUTPUTS) {
                fprintf(stderr, "fmi_driver: more than %d outputs in the plan (at: %s)\n",
                        MAX_OUTPUTS, line);
                return 2;
            }
            outputs[n_outputs].kind = strcmp(a, "real") == 0  ? KIND_REAL
                                      : strcmp(a, "int") == 0 ? KIND_INT
                                                              : KIND_BOOL;
            outputs[n_outputs++].vr = vr;
        } else if (strcmp(command, "init") == 0 && sscanf(line, "init %s %s", a, b) == 2) {
            t = bits_to_double(a);
            initialize(&f, t, bits_to_double(b));
        } else if (strcmp(command, "step") == 0 && sscanf(line, "step %s %s", a, b) == 2) {
            double h = bits_to_double(a);
            long n = atol(b), k;
            for (k = 0; k < n; k++) {
                size_t i;
                do_step(&f, t, h);
                t += h;
                printf("t=");
                print_double(t);
                for (i = 0; i < n_outputs; i++)
                    print_output(&f, &outputs[i]);
                putchar('\n');
            }
        } else {
            fprintf(stderr, "fmi_driver: bad plan line: %s\n", line);
            return 2;
        }
    }
    finish(&f);
    fflush(stdout);
    return 0;
}
