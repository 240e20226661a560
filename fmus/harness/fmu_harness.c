/* fmu_harness.c: a minimal FMI 2.0 Co-Simulation importer in C, for robustness checks
 * of the gearbox FMUs (and a short run under valgrind):
 *
 *   fmu_harness DIR IDENTIFIER GUID VR_OUT VR_PARAM CYCLES
 *
 * DIR is an unzipped FMU. The harness
 *   1. instantiates, initialises, steps and frees the FMU CYCLES times;
 *   2. runs three instances side by side with the parameter VR_PARAM scaled by 1, 1.1,
 *      1.2, then a fresh instance with the first value: its output VR_OUT must equal
 *      the first instance's bit for bit (no state shared between instances);
 *   3. sets VR_PARAM to -1 and to 0: fmi2SetReal must return fmi2Error, log a message
 *      that names the parameter, and leave the value unchanged; stepping goes on.
 * It prints one line per check and exits 0 when all pass. Build:
 *   cc -std=c11 -Wall -Wextra -Werror -I <sources> fmu_harness.c -ldl -o fmu_harness
 */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

static char last_message[2048];
static int n_errors_logged;

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
    va_list ap;
    (void)env;
    (void)name;
    (void)category;
    va_start(ap, message);
    vsnprintf(last_message, sizeof last_message, message, ap);
    va_end(ap);
    if (status >= fmi2Error) n_errors_logged++;
}

typedef struct {
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2SetupExperimentTYPE *setup;
    fmi2EnterInitializationModeTYPE *enter_init;
    fmi2ExitInitializationModeTYPE *exit_init;
    fmi2DoStepTYPE *do_step;
    fmi2GetRealTYPE *get_real;
    fmi2SetRealTYPE *set_real;
    fmi2TerminateTYPE *terminate;
} Api;

static int failures;

static void check(int ok, const char *what) {
    printf("%s %s\n", ok ? "ok  " : "FAIL", what);
    if (!ok) failures++;
}

static void *sym(void *lib, const char *name) {
    void *p = dlsym(lib, name);
    if (!p) {
        fprintf(stderr, "missing symbol %s\n", name);
        exit(2);
    }
    return p;
}

static fmi2Component start(const Api *api, const fmi2CallbackFunctions *cb, const char *guid,
                           const char *uri, const char *name, fmi2ValueReference vrp, double scale) {
    fmi2Component c = api->instantiate(name, fmi2CoSimulation, guid, uri, cb, fmi2False, fmi2False);
    double p;
    if (!c) return NULL;
    api->setup(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    api->enter_init(c);
    api->get_real(c, &vrp, 1, &p);
    p *= scale;
    api->set_real(c, &vrp, 1, &p);
    if (api->exit_init(c) != fmi2OK) {
        api->free_instance(c);
        return NULL;
    }
    return c;
}

int main(int argc, char **argv) {
    char path[4096], uri[4200];
    void *lib;
    Api api;
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2ValueReference vro, vrp;
    int cycles, i, k;
    const double h = 1e-4;
    if (argc != 7) {
        fprintf(stderr, "usage: fmu_harness DIR IDENTIFIER GUID VR_OUT VR_PARAM CYCLES\n");
        return 2;
    }
    vro = (fmi2ValueReference)atoi(argv[4]);
    vrp = (fmi2ValueReference)atoi(argv[5]);
    cycles = atoi(argv[6]);
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", argv[1], argv[2]);
    snprintf(uri, sizeof uri, "file://%s/resources", argv[1]);
    lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "cannot load %s: %s\n", path, dlerror());
        return 2;
    }
    *(void **)&api.instantiate = sym(lib, "fmi2Instantiate");
    *(void **)&api.free_instance = sym(lib, "fmi2FreeInstance");
    *(void **)&api.setup = sym(lib, "fmi2SetupExperiment");
    *(void **)&api.enter_init = sym(lib, "fmi2EnterInitializationMode");
    *(void **)&api.exit_init = sym(lib, "fmi2ExitInitializationMode");
    *(void **)&api.do_step = sym(lib, "fmi2DoStep");
    *(void **)&api.get_real = sym(lib, "fmi2GetReal");
    *(void **)&api.set_real = sym(lib, "fmi2SetReal");
    *(void **)&api.terminate = sym(lib, "fmi2Terminate");

    { /* 1. instantiate / free cycles */
        int ok = 1;
        for (k = 0; k < cycles && ok; k++) {
            fmi2Component c = start(&api, &cb, argv[3], uri, "cycle", vrp, 1.0);
            double y = 0.0;
            if (!c) {
                ok = 0;
                break;
            }
            for (i = 0; i < 5; i++) ok &= api.do_step(c, i * h, h, fmi2True) == fmi2OK;
            ok &= api.get_real(c, &vro, 1, &y) == fmi2OK && y == y;
            api.terminate(c);
            api.free_instance(c);
        }
        printf("cycles %d\n", k);
        check(ok && k == cycles, "instantiate / step / free cycles");
    }
    { /* 2. several instances */
        fmi2Component c[4];
        double y[4] = {0, 0, 0, 0};
        int ok = 1;
        for (k = 0; k < 3; k++) c[k] = start(&api, &cb, argv[3], uri, "side_by_side", vrp, 1.0 + 0.1 * k);
        ok = c[0] && c[1] && c[2];
        for (i = 0; ok && i < 50; i++)
            for (k = 0; k < 3; k++) ok &= api.do_step(c[k], i * h, h, fmi2True) == fmi2OK;
        for (k = 0; ok && k < 3; k++) api.get_real(c[k], &vro, 1, &y[k]);
        c[3] = start(&api, &cb, argv[3], uri, "fresh", vrp, 1.0);
        ok &= c[3] != NULL;
        for (i = 0; ok && i < 50; i++) ok &= api.do_step(c[3], i * h, h, fmi2True) == fmi2OK;
        if (ok) api.get_real(c[3], &vro, 1, &y[3]);
        printf("outputs %.17g %.17g %.17g %.17g\n", y[0], y[1], y[2], y[3]);
        check(ok, "three instances side by side step");
        check(ok && y[0] != y[1] && y[1] != y[2], "instances keep their own parameters");
        check(ok && y[3] == y[0], "a fresh instance reproduces the first bit for bit");
        for (k = 0; k < 4; k++)
            if (c[k]) {
                api.terminate(c[k]);
                api.free_instance(c[k]);
            }
    }
    { /* 3. invalid parameters through the API */
        fmi2Component c = start(&api, &cb, argv[3], uri, "invalid", vrp, 1.0);
        double before = 0.0, after = 0.0, bad[2] = {-1.0, 0.0};
        int ok = c != NULL;
        for (k = 0; ok && k < 2; k++) {
            int logged = n_errors_logged;
            fmi2Status s;
            api.get_real(c, &vrp, 1, &before);
            s = api.set_real(c, &vrp, 1, &bad[k]);
            api.get_real(c, &vrp, 1, &after);
            printf("set %g -> status %d, message: %s\n", bad[k], (int)s, last_message);
            check(s == fmi2Error, "invalid value returns fmi2Error");
            check(n_errors_logged > logged && strstr(last_message, "is invalid") != NULL,
                  "and logs a message");
            check(after == before, "and leaves the value unchanged");
        }
        for (i = 0; ok && i < 5; i++) ok &= api.do_step(c, i * h, h, fmi2True) == fmi2OK;
        check(ok, "stepping goes on after rejected values");
        if (c) {
            api.terminate(c);
            api.free_instance(c);
        }
    }
    dlclose(lib);
    printf("%s\n", failures ? "FAILED" : "PASSED");
    return failures ? 1 : 0;
}
