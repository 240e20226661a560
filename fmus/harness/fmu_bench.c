/* fmu_bench.c: wall time of a Co-Simulation run of an unzipped FMU, in C (no importer
 * overhead beyond one function call per communication step):
 *
 *   fmu_bench DIR IDENTIFIER GUID SETTINGS STOP STEP REPEATS
 *
 * SETTINGS: "VR=VALUE[,VR=VALUE...]", real parameters set in initialization mode (value
 * references, e.g. the integrator's solver.method and solver.rtol).
 * Prints the median and the smallest wall time of the doStep calls over REPEATS runs of
 * STOP seconds with communication step STEP (STEP = STOP: one doStep), and the
 * real-time factor of the median (instantiation and initialization are not timed).
 * Build:
 *   cc -std=c11 -O2 -I <sources> fmu_bench.c -ldl -o fmu_bench
 */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
    (void)env;
    (void)name;
    (void)category;
    if (status >= fmi2Error) fprintf(stderr, "error: %s\n", message);
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv) {
    char path[4096], uri[4200];
    void *lib;
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2ValueReference vrs[16];
    double vals[16], stop, step, walls[101];
    int repeats, r, nset = 0;
    const char *p;
    fmi2InstantiateTYPE *inst;
    fmi2FreeInstanceTYPE *fre;
    fmi2SetupExperimentTYPE *setup;
    fmi2EnterInitializationModeTYPE *enter;
    fmi2ExitInitializationModeTYPE *exit_;
    fmi2DoStepTYPE *step_fn;
    fmi2SetRealTYPE *set;
    if (argc != 8) {
        fprintf(stderr, "usage: fmu_bench DIR IDENTIFIER GUID SETTINGS STOP STEP REPEATS\n");
        return 2;
    }
    for (p = argv[4]; *p && nset < 16;) {
        char *end;
        vrs[nset] = (fmi2ValueReference)strtoul(p, &end, 10);
        if (*end != '=') return 2;
        vals[nset++] = strtod(end + 1, &end);
        if (*end != ',' && *end != 0) return 2;
        p = *end ? end + 1 : end;
    }
    stop = atof(argv[5]);
    step = atof(argv[6]);
    repeats = atoi(argv[7]);
    if (repeats < 1 || repeats > 101 || !(step > 0) || !(stop >= step)) return 2;
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", argv[1], argv[2]);
    snprintf(uri, sizeof uri, "file://%s/resources", argv[1]);
    lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "cannot load %s: %s\n", path, dlerror());
        return 2;
    }
    *(void **)&inst = dlsym(lib, "fmi2Instantiate");
    *(void **)&fre = dlsym(lib, "fmi2FreeInstance");
    *(void **)&setup = dlsym(lib, "fmi2SetupExperiment");
    *(void **)&enter = dlsym(lib, "fmi2EnterInitializationMode");
    *(void **)&exit_ = dlsym(lib, "fmi2ExitInitializationMode");
    *(void **)&step_fn = dlsym(lib, "fmi2DoStep");
    *(void **)&set = dlsym(lib, "fmi2SetReal");
    for (r = 0; r < repeats; r++) {
        struct timespec a, b;
        long i, n = (long)(stop / step + 0.5);
        fmi2Component c = inst("bench", fmi2CoSimulation, argv[3], uri, &cb, fmi2False, fmi2False);
        if (!c) return 1;
        setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
        enter(c);
        if (nset && set(c, vrs, (size_t)nset, vals) != fmi2OK) return 1;
        if (exit_(c) != fmi2OK) return 1;
        clock_gettime(CLOCK_MONOTONIC, &a);
        for (i = 0; i < n; i++)
            if (step_fn(c, i * step, step, fmi2True) != fmi2OK) return 1;
        clock_gettime(CLOCK_MONOTONIC, &b);
        walls[r] = (double)(b.tv_sec - a.tv_sec) + 1e-9 * (double)(b.tv_nsec - a.tv_nsec);
        fre(c);
    }
    qsort(walls, (size_t)repeats, sizeof(double), cmp);
    printf("median wall %.6f s over %d runs, %.1f x real time, min %.6f s\n", walls[repeats / 2],
           repeats, stop / walls[repeats / 2], walls[0]);
    dlclose(lib);
    return 0;
}
