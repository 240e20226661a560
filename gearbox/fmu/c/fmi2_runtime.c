/* fmi2_runtime.c: generic FMI 2.0 runtime for the gearbox FMUs, Model Exchange and
 * Co-Simulation in one binary.
 *
 * The model (model.c, config.h) supplies equations and tables; this file supplies the
 * FMI state machine, argument checks with a logged message on every error, memory
 * through the importer's callbacks, the resource folder, and the internal
 * Co-Simulation integrators: Dormand-Prince 5(4) with step-size control (Hairer,
 * Norsett, Wanner, "Solving Ordinary Differential Equations I", 2nd ed., Sec. II.4
 * (error estimate and step control, eqs. (4.10)-(4.13)) and Sec. II.5, Table 5.2
 * (coefficients)), and fixed-step Tsitouras 5(4) (Ch. Tsitouras, "Runge-Kutta pairs of
 * order 5(4) satisfying only the first column simplifying assumption", Comput. Math.
 * Appl. 62 (2011) 770-775) with the step of gearbox.drivetrain.fixed_step: 1 /
 * (steps_per_period f_max), f_max the larger of the highest eigenfrequency of the
 * model linearised with the mesh at its largest stiffness and the forcing frequency,
 * at most 0.8 x the method's stability limit on that linear system. A fixed step that
 * ends out of the nominal mesh contact is taken again with adaptive DOPRI5 steps, and
 * the following intervals too until the contact is back.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gbx_model.h"

/* The FMI 2.0 functions are defined as GBX2(name): fmi2<name> in an FMI 2.0 build, and
 * gbx_fmi2<name> (internal) in an FMI 3.0 build, where fmi3_runtime.c adapts them. */
#if defined(GBX_FMI3)
#define GBX2(name) gbx_fmi2##name
#else
#define GBX2(name) fmi2##name
#endif

#define GBX_MAX_SUBSTEPS 10000000L
#define TWO_PI_RT 6.283185307179586

/* ------------------------------------------------------------------ services */

void *gbx_calloc(const ModelInstance *m, size_t n, size_t size) {
    if (m->cb.allocateMemory) return m->cb.allocateMemory(n, size);
    return calloc(n, size);
}

void gbx_free(const ModelInstance *m, void *p) {
    if (!p) return;
    if (m->cb.freeMemory)
        m->cb.freeMemory(p);
    else
        free(p);
}

void gbx_log(const ModelInstance *m, fmi2Status status, const char *category, const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    if (!m || !m->cb.logger) return;
    if (status == fmi2OK && !m->logging) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    /* the message goes through "%s": the logger treats its argument as a format */
    m->cb.logger(m->cb.componentEnvironment, m->name, status, category, "%s", buf);
}

static char *dup_string(const ModelInstance *m, const char *s) {
    size_t n = strlen(s);
    char *d = (char *)gbx_calloc(m, n + 1, 1);
    if (d) memcpy(d, s, n + 1);
    return d;
}

/* file:///a/b%20c/resources -> /a/b c/resources; NULL when not a local file URI. */
static char *uri_to_path(const ModelInstance *m, const char *uri) {
    const char *p;
    char *out, *o;
    if (!uri) return NULL;
    if (strncmp(uri, "file:///", 8) == 0)
        p = uri + 7;
    else if (strncmp(uri, "file://localhost/", 17) == 0)
        p = uri + 16;
    else if (strncmp(uri, "file:/", 6) == 0)
        p = uri + 5;
    else
        return NULL;
    out = (char *)gbx_calloc(m, strlen(p) + 1, 1);
    if (!out) return NULL;
    for (o = out; *p; p++) {
        if (p[0] == '%' && p[1] && p[2]) {
            char hex[3] = {p[1], p[2], 0};
            char *end;
            long c = strtol(hex, &end, 16);
            if (*end == 0) {
                *o++ = (char)c;
                p += 2;
                continue;
            }
        }
        *o++ = *p;
    }
    *o = 0;
    while (o > out + 1 && o[-1] == '/') *--o = 0;
    return out;
}

int gbx_read_table(ModelInstance *m, const char *file, int *rows, int *cols, double **data) {
    char path[4096];
    char line[512];
    FILE *f;
    int version = 0;
    long n, i;
    double *d;
    *data = NULL;
    snprintf(path, sizeof path, "%s/%s", m->resource_dir ? m->resource_dir : ".", file);
    f = fopen(path, "r");
    if (!f) {
        gbx_log(m, fmi2Error, "logStatusError", "cannot open resource table '%s'", path);
        return 1;
    }
    if (!fgets(line, sizeof line, f) ||
        sscanf(line, "gearbox-table %d %d %d", &version, rows, cols) != 3 || version != 1 ||
        *rows < 1 || *cols < 1 || *rows > 100000 || *cols > 1000) {
        gbx_log(m, fmi2Error, "logStatusError",
                "resource table '%s' is corrupt: first line must be 'gearbox-table 1 <rows> <cols>'",
                path);
        fclose(f);
        return 1;
    }
    n = (long)*rows * (long)*cols;
    d = (double *)gbx_calloc(m, (size_t)n, sizeof(double));
    if (!d) {
        fclose(f);
        gbx_log(m, fmi2Error, "logStatusError", "out of memory reading '%s'", path);
        return 1;
    }
    i = 0;
    while (i < n) {
        int c = fgetc(f);
        if (c == EOF) break;
        if (c == '#') { /* comment to end of line */
            while (c != EOF && c != '\n') c = fgetc(f);
            continue;
        }
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ',') continue;
        ungetc(c, f);
        if (fscanf(f, "%lf", &d[i]) != 1 || !isfinite(d[i])) {
            gbx_log(m, fmi2Error, "logStatusError",
                    "resource table '%s' is corrupt: value %ld of %ld is not a finite number", path,
                    i + 1, n);
            gbx_free(m, d);
            fclose(f);
            return 1;
        }
        i++;
    }
    fclose(f);
    if (i != n) {
        gbx_log(m, fmi2Error, "logStatusError",
                "resource table '%s' is corrupt: %ld numbers found, %d x %d = %ld expected", path, i,
                *rows, *cols, n);
        gbx_free(m, d);
        return 1;
    }
    *data = d;
    return 0;
}

/* ------------------------------------------------------------ argument checks */

#define MASK_INSTANTIATED (1 << GBX_ST_INSTANTIATED)
#define MASK_INIT (1 << GBX_ST_INIT)
#define MASK_EVENT (1 << GBX_ST_EVENT)
#define MASK_CONT (1 << GBX_ST_CONT)
#define MASK_STEP (1 << GBX_ST_STEP)
#define MASK_TERMINATED (1 << GBX_ST_TERMINATED)
#define MASK_ERROR (1 << GBX_ST_ERROR)
#define MASK_ANY 0x7f

static const char *STATE_NAMES[] = {"instantiated", "initialization mode", "event mode",
                                    "continuous-time mode", "step mode", "terminated", "error"};

static int not_allowed(ModelInstance *m, const char *fn, int mask) {
    if (!m) return 1;
    if (mask & (1 << m->state)) return 0;
    gbx_log(m, fmi2Error, "logStatusError", "%s must not be called in state '%s'", fn,
            STATE_NAMES[m->state]);
    m->state = GBX_ST_ERROR;
    return 1;
}

static int null_arg(ModelInstance *m, const char *fn, const char *arg, const void *p, size_t n) {
    if (n == 0 || p) return 0;
    gbx_log(m, fmi2Error, "logStatusError", "%s: argument %s must not be NULL", fn, arg);
    m->state = GBX_ST_ERROR;
    return 1;
}

static int bad_vr(ModelInstance *m, const char *fn, fmi2ValueReference vr) {
    if (vr < GBX_NR) return 0;
    gbx_log(m, fmi2Error, "logStatusError", "%s: unknown value reference %u (valid: 0..%d)", fn,
            (unsigned)vr, GBX_NR - 1);
    return 1;
}

static int fixed_step_rule(ModelInstance *m, char *msg, size_t n);

static int update(ModelInstance *m, const char *fn) {
    char msg[512];
    msg[0] = 0;
    if (gbx_model_update(m, msg, sizeof msg) != 0 || fixed_step_rule(m, msg, sizeof msg) != 0) {
        gbx_log(m, fmi2Error, "logStatusError", "%s: invalid parameters: %s", fn, msg);
        return 1;
    }
    return 0;
}

static int refresh_initial_state(ModelInstance *m, const char *fn) {
    if (m->x_pending && (m->state == GBX_ST_INSTANTIATED || m->state == GBX_ST_INIT)) {
        if (update(m, fn) != 0) return 1;
        gbx_model_initial_state(m);
        m->x_pending = 0;
    }
    return 0;
}

static void reset_values(ModelInstance *m) {
    int i;
    for (i = 0; i < GBX_NR; i++) m->r[i] = GBX_VARS[i].start;
    for (i = 0; i < GBX_NX_ALLOC; i++) m->x[i] = 0.0;
    m->time = 0.0;
    m->t_input = 0.0;
    m->x_pending = 1;
    m->h = 0.0;
    m->fsal_valid = 0;
    m->n_steps = m->n_rejected = m->n_rhs = 0;
    m->out_of_contact = 0;
    m->n_handed_over = 0;
}

/* ----------------------------------------------------------- common functions */

const char *GBX2(GetTypesPlatform)(void) { return fmi2TypesPlatform; }
const char *GBX2(GetVersion)(void) { return fmi2Version; }

fmi2Status GBX2(SetDebugLogging)(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    ModelInstance *m = (ModelInstance *)c;
    (void)categories;
    if (not_allowed(m, "fmi2SetDebugLogging", MASK_ANY)) return fmi2Error;
    if (null_arg(m, "fmi2SetDebugLogging", "categories", categories, nCategories)) return fmi2Error;
    m->logging = loggingOn ? 1 : 0;
    return fmi2OK;
}

fmi2Component GBX2(Instantiate)(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    ModelInstance tmp, *m;
    (void)visible;
    if (!functions) return NULL;
    memset(&tmp, 0, sizeof tmp);
    tmp.cb = *functions;
    tmp.name = (char *)(instanceName ? instanceName : "?");
    tmp.logging = loggingOn ? 1 : 0;
    if (!instanceName || !*instanceName) {
        gbx_log(&tmp, fmi2Error, "logStatusError", "fmi2Instantiate: instanceName must be non-empty");
        return NULL;
    }
    if (!fmuGUID || strcmp(fmuGUID, MODEL_GUID) != 0) {
        gbx_log(&tmp, fmi2Error, "logStatusError", "fmi2Instantiate: GUID '%s' does not match '%s'",
                fmuGUID ? fmuGUID : "(null)", MODEL_GUID);
        return NULL;
    }
    if (fmuType != fmi2ModelExchange && fmuType != fmi2CoSimulation) {
        gbx_log(&tmp, fmi2Error, "logStatusError", "fmi2Instantiate: unknown fmuType %d", (int)fmuType);
        return NULL;
    }
    m = (ModelInstance *)gbx_calloc(&tmp, 1, sizeof(ModelInstance));
    if (!m) {
        gbx_log(&tmp, fmi2Error, "logStatusError", "fmi2Instantiate: out of memory");
        return NULL;
    }
    m->cb = *functions;
    m->logging = tmp.logging;
    m->type = fmuType;
    m->name = dup_string(m, instanceName);
    m->resource_dir = uri_to_path(m, fmuResourceLocation);
    if (!m->name) {
        gbx_free(m, m->resource_dir);
        gbx_free(m, m);
        return NULL;
    }
    if (!m->resource_dir) {
        gbx_log(m, fmi2Error, "logStatusError",
                "fmi2Instantiate: fmuResourceLocation '%s' is not a local file URI (file:///...); "
                "the model needs its tables from resources/",
                fmuResourceLocation ? fmuResourceLocation : "(null)");
        gbx_free(m, m->name);
        gbx_free(m, m);
        return NULL;
    }
    reset_values(m);
    if (gbx_model_load(m) != 0) {
        gbx_log(m, fmi2Error, "logStatusError", "fmi2Instantiate: loading the model tables from '%s' failed",
                m->resource_dir);
        gbx_model_free(m);
        gbx_free(m, m->resource_dir);
        gbx_free(m, m->name);
        gbx_free(m, m);
        return NULL;
    }
    m->state = GBX_ST_INSTANTIATED;
    gbx_log(m, fmi2OK, "logEvents", "instantiated (%s)",
            fmuType == fmi2CoSimulation ? "Co-Simulation" : "Model Exchange");
    return m;
}

void GBX2(FreeInstance)(fmi2Component c) {
    ModelInstance *m = (ModelInstance *)c;
    if (!m) return;
    gbx_log(m, fmi2OK, "logEvents", "freed after %ld steps, %ld rejected, %ld right-hand sides",
            m->n_steps, m->n_rejected, m->n_rhs);
    gbx_model_free(m);
    gbx_free(m, m->resource_dir);
    gbx_free(m, m->name);
    gbx_free(m, m);
}

fmi2Status GBX2(SetupExperiment)(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    ModelInstance *m = (ModelInstance *)c;
    (void)stopTimeDefined;
    (void)stopTime;
    if (not_allowed(m, "fmi2SetupExperiment", MASK_INSTANTIATED)) return fmi2Error;
    if (!isfinite(startTime)) {
        gbx_log(m, fmi2Error, "logStatusError", "fmi2SetupExperiment: startTime = %g must be finite",
                startTime);
        return fmi2Error;
    }
    if (toleranceDefined && m->type == fmi2CoSimulation) {
        if (!(tolerance > 0.0 && tolerance < 1.0)) {
            gbx_log(m, fmi2Error, "logStatusError",
                    "fmi2SetupExperiment: tolerance = %g must be in (0, 1)", tolerance);
            return fmi2Error;
        }
        m->r[GBX_VR_SOLVER_RTOL] = tolerance;
    }
    m->time = startTime;
    m->t_input = startTime;
    m->x_pending = 1;
    return fmi2OK;
}

fmi2Status GBX2(EnterInitializationMode)(fmi2Component c) {
    ModelInstance *m = (ModelInstance *)c;
    if (not_allowed(m, "fmi2EnterInitializationMode", MASK_INSTANTIATED)) return fmi2Error;
    m->state = GBX_ST_INIT;
    m->x_pending = 1;
    return fmi2OK;
}

fmi2Status GBX2(ExitInitializationMode)(fmi2Component c) {
    ModelInstance *m = (ModelInstance *)c;
    if (not_allowed(m, "fmi2ExitInitializationMode", MASK_INIT)) return fmi2Error;
    m->x_pending = 1;
    if (refresh_initial_state(m, "fmi2ExitInitializationMode") != 0) {
        m->state = GBX_ST_ERROR;
        return fmi2Error;
    }
    m->state = m->type == fmi2CoSimulation ? GBX_ST_STEP : GBX_ST_EVENT;
    m->h = 0.0;
    m->fsal_valid = 0;
    m->out_of_contact = 0;
    return fmi2OK;
}

fmi2Status GBX2(Terminate)(fmi2Component c) {
    ModelInstance *m = (ModelInstance *)c;
    if (not_allowed(m, "fmi2Terminate", MASK_EVENT | MASK_CONT | MASK_STEP | MASK_ERROR))
        return fmi2Error;
    gbx_log(m, fmi2OK, "logEvents", "terminated at t = %g s after %ld steps (%ld rejected)",
            m->time, m->n_steps, m->n_rejected);
    m->state = GBX_ST_TERMINATED;
    return fmi2OK;
}

fmi2Status GBX2(Reset)(fmi2Component c) {
    ModelInstance *m = (ModelInstance *)c;
    if (not_allowed(m, "fmi2Reset", MASK_ANY)) return fmi2Error;
    reset_values(m);
    m->state = GBX_ST_INSTANTIATED;
    return fmi2OK;
}

/* ------------------------------------------------------------- get / set */

fmi2Status GBX2(GetReal)(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    ModelInstance *m = (ModelInstance *)c;
    size_t i;
    int outputs_done = 0, derivs_done = 0;
    double dx[GBX_NX_ALLOC];
    if (not_allowed(m, "fmi2GetReal", MASK_INIT | MASK_EVENT | MASK_CONT | MASK_STEP |
                                          MASK_TERMINATED | MASK_ERROR))
        return fmi2Error;
    if (null_arg(m, "fmi2GetReal", "vr", vr, nvr) || null_arg(m, "fmi2GetReal", "value", value, nvr))
        return fmi2Error;
    if (refresh_initial_state(m, "fmi2GetReal") != 0) return fmi2Error;
    for (i = 0; i < nvr; i++) {
        const gbx_var *v;
        if (bad_vr(m, "fmi2GetReal", vr[i])) return fmi2Error;
        v = &GBX_VARS[vr[i]];
        switch (v->kind) {
        case GBX_STATE:
            value[i] = m->x[v->index];
            break;
        case GBX_DERIVATIVE:
            if (!derivs_done) {
                gbx_model_derivatives(m, m->time, m->x, dx);
                m->n_rhs++;
                derivs_done = 1;
            }
            value[i] = dx[v->index];
            break;
        case GBX_OUTPUT:
            if (!outputs_done) {
                gbx_model_outputs(m, m->time, m->x);
                m->r[GBX_VR_SOLVER_STEPS] = (double)m->n_steps;
                m->r[GBX_VR_SOLVER_REJECTED] = (double)m->n_rejected;
                m->r[GBX_VR_SOLVER_RHS] = (double)m->n_rhs;
                m->r[GBX_VR_SOLVER_STEP_SIZE] = m->fs_step;
                m->r[GBX_VR_SOLVER_STABILITY_LIMIT] = m->fs_limit;
                m->r[GBX_VR_SOLVER_HANDED_OVER] = (double)m->n_handed_over;
                outputs_done = 1;
            }
            value[i] = m->r[vr[i]];
            break;
        default:
            value[i] = m->r[vr[i]];
        }
    }
    return fmi2OK;
}

fmi2Status GBX2(SetReal)(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
    ModelInstance *m = (ModelInstance *)c;
    size_t i;
    int changed_parameter = 0;
    double old[GBX_NR];
    if (not_allowed(m, "fmi2SetReal", MASK_INSTANTIATED | MASK_INIT | MASK_EVENT | MASK_CONT | MASK_STEP))
        return fmi2Error;
    if (null_arg(m, "fmi2SetReal", "vr", vr, nvr) || null_arg(m, "fmi2SetReal", "value", value, nvr))
        return fmi2Error;
    /* check everything first, so that a rejected call changes nothing */
    for (i = 0; i < nvr; i++) {
        const gbx_var *v;
        double x = value[i];
        int ok;
        if (bad_vr(m, "fmi2SetReal", vr[i])) return fmi2Error;
        v = &GBX_VARS[vr[i]];
        if (v->kind != GBX_PARAMETER && v->kind != GBX_INPUT) {
            gbx_log(m, fmi2Error, "logStatusError",
                    "fmi2SetReal: variable '%s' (vr %u) is calculated and cannot be set", v->name,
                    (unsigned)vr[i]);
            return fmi2Error;
        }
        if (v->kind == GBX_PARAMETER && v->fixed && m->state != GBX_ST_INSTANTIATED &&
            m->state != GBX_ST_INIT) {
            gbx_log(m, fmi2Error, "logStatusError",
                    "fmi2SetReal: parameter '%s' is fixed: set it before initialization ends",
                    v->name);
            return fmi2Error;
        }
        if (v->kind == GBX_PARAMETER && m->state == GBX_ST_CONT) {
            gbx_log(m, fmi2Error, "logStatusError",
                    "fmi2SetReal: parameter '%s' can be changed in event mode, not in "
                    "continuous-time mode", v->name);
            return fmi2Error;
        }
        ok = isfinite(x) && (v->min_open ? x > v->min : x >= v->min) &&
             (v->max_open ? x < v->max : x <= v->max);
        if (ok && vr[i] == GBX_VR_SOLVER_METHOD && x != 0.0 && x != 1.0) {
            gbx_log(m, fmi2Error, "logStatusError",
                    "fmi2SetReal: %s = %g is invalid: must be 0 (adaptive DOPRI5) or 1 "
                    "(fixed-step Tsit5)", v->name, x);
            return fmi2Error;
        }
        if (!ok) {
            gbx_log(m, fmi2Error, "logStatusError",
                    "fmi2SetReal: %s = %g is invalid: must be in %s%g, %g%s", v->name, x,
                    v->min_open || isinf(v->min) ? "(" : "[", v->min, v->max,
                    v->max_open || isinf(v->max) ? ")" : "]");
            return fmi2Error;
        }
    }
    memcpy(old, m->r, sizeof old);
    for (i = 0; i < nvr; i++) {
        m->r[vr[i]] = value[i];
        if (GBX_VARS[vr[i]].kind == GBX_PARAMETER) changed_parameter = 1;
    }
    if (changed_parameter && (m->state == GBX_ST_STEP || m->state == GBX_ST_EVENT)) {
        if (update(m, "fmi2SetReal") != 0) {
            char msg[512];
            memcpy(m->r, old, sizeof old); /* a rejected call changes nothing */
            gbx_model_update(m, msg, sizeof msg);
            return fmi2Error;
        }
    }
    if (changed_parameter && (m->state == GBX_ST_INSTANTIATED || m->state == GBX_ST_INIT))
        m->x_pending = 1;
    m->fsal_valid = 0;
    m->t_input = m->time;
    return fmi2OK;
}

#define NO_VARIABLES(kind, ctype)                                                                  \
    fmi2Status GBX2(Get##kind)(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,          \
                             ctype value[]) {                                                      \
        ModelInstance *m = (ModelInstance *)c;                                                     \
        (void)vr;                                                                                  \
        (void)value;                                                                               \
        if (not_allowed(m, "fmi2Get" #kind, MASK_ANY)) return fmi2Error;                           \
        if (nvr == 0) return fmi2OK;                                                               \
        gbx_log(m, fmi2Error, "logStatusError", "fmi2Get" #kind ": the model has no such variables"); \
        return fmi2Error;                                                                          \
    }                                                                                              \
    fmi2Status GBX2(Set##kind)(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,          \
                             const ctype value[]) {                                                \
        ModelInstance *m = (ModelInstance *)c;                                                     \
        (void)vr;                                                                                  \
        (void)value;                                                                               \
        if (not_allowed(m, "fmi2Set" #kind, MASK_ANY)) return fmi2Error;                           \
        if (nvr == 0) return fmi2OK;                                                               \
        gbx_log(m, fmi2Error, "logStatusError", "fmi2Set" #kind ": the model has no such variables"); \
        return fmi2Error;                                                                          \
    }

NO_VARIABLES(Integer, fmi2Integer)
NO_VARIABLES(Boolean, fmi2Boolean)
NO_VARIABLES(String, fmi2String)

/* ------------------------------------------- FMU state, directional derivatives */

#define UNSUPPORTED(fn)                                                                            \
    {                                                                                              \
        ModelInstance *m = (ModelInstance *)c;                                                     \
        if (m) gbx_log(m, fmi2Error, "logStatusError", fn " is not supported by this FMU");        \
        return fmi2Error;                                                                          \
    }

fmi2Status GBX2(GetFMUstate)(fmi2Component c, fmi2FMUstate *s) {
    (void)s;
    UNSUPPORTED("fmi2GetFMUstate")
}
fmi2Status GBX2(SetFMUstate)(fmi2Component c, fmi2FMUstate s) {
    (void)s;
    UNSUPPORTED("fmi2SetFMUstate")
}
fmi2Status GBX2(FreeFMUstate)(fmi2Component c, fmi2FMUstate *s) {
    (void)s;
    UNSUPPORTED("fmi2FreeFMUstate")
}
fmi2Status GBX2(SerializedFMUstateSize)(fmi2Component c, fmi2FMUstate s, size_t *n) {
    (void)s;
    (void)n;
    UNSUPPORTED("fmi2SerializedFMUstateSize")
}
fmi2Status GBX2(SerializeFMUstate)(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n) {
    (void)s;
    (void)b;
    (void)n;
    UNSUPPORTED("fmi2SerializeFMUstate")
}
fmi2Status GBX2(DeSerializeFMUstate)(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *s) {
    (void)s;
    (void)b;
    (void)n;
    UNSUPPORTED("fmi2DeSerializeFMUstate")
}
fmi2Status GBX2(GetDirectionalDerivative)(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz,
                                        const fmi2Real dv[], fmi2Real dz[]) {
    (void)u;
    (void)nu;
    (void)z;
    (void)nz;
    (void)dv;
    (void)dz;
    UNSUPPORTED("fmi2GetDirectionalDerivative")
}

/* ------------------------------------------------------------ Model Exchange */

fmi2Status GBX2(EnterEventMode)(fmi2Component c) {
    ModelInstance *m = (ModelInstance *)c;
    if (not_allowed(m, "fmi2EnterEventMode", MASK_EVENT | MASK_CONT)) return fmi2Error;
    m->state = GBX_ST_EVENT;
    return fmi2OK;
}

fmi2Status GBX2(NewDiscreteStates)(fmi2Component c, fmi2EventInfo *info) {
    ModelInstance *m = (ModelInstance *)c;
    if (not_allowed(m, "fmi2NewDiscreteStates", MASK_EVENT)) return fmi2Error;
    if (null_arg(m, "fmi2NewDiscreteStates", "fmi2eventInfo", info, 1)) return fmi2Error;
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    return fmi2OK;
}

fmi2Status GBX2(EnterContinuousTimeMode)(fmi2Component c) {
    ModelInstance *m = (ModelInstance *)c;
    if (not_allowed(m, "fmi2EnterContinuousTimeMode", MASK_EVENT)) return fmi2Error;
    m->state = GBX_ST_CONT;
    return fmi2OK;
}

fmi2Status GBX2(CompletedIntegratorStep)(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    ModelInstance *m = (ModelInstance *)c;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (not_allowed(m, "fmi2CompletedIntegratorStep", MASK_CONT)) return fmi2Error;
    if (null_arg(m, "fmi2CompletedIntegratorStep", "enterEventMode", enterEventMode, 1) ||
        null_arg(m, "fmi2CompletedIntegratorStep", "terminateSimulation", terminateSimulation, 1))
        return fmi2Error;
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    m->n_steps++;
    return fmi2OK;
}

fmi2Status GBX2(SetTime)(fmi2Component c, fmi2Real time) {
    ModelInstance *m = (ModelInstance *)c;
    if (not_allowed(m, "fmi2SetTime", MASK_EVENT | MASK_CONT)) return fmi2Error;
    if (!isfinite(time)) {
        gbx_log(m, fmi2Error, "logStatusError", "fmi2SetTime: time = %g must be finite", time);
        return fmi2Error;
    }
    m->time = time;
    m->t_input = time;
    return fmi2OK;
}

fmi2Status GBX2(SetContinuousStates)(fmi2Component c, const fmi2Real x[], size_t nx) {
    ModelInstance *m = (ModelInstance *)c;
    size_t i;
    if (not_allowed(m, "fmi2SetContinuousStates", MASK_EVENT | MASK_CONT)) return fmi2Error;
    if (nx != GBX_NX) {
        gbx_log(m, fmi2Error, "logStatusError", "fmi2SetContinuousStates: nx = %u, expected %d",
                (unsigned)nx, GBX_NX);
        return fmi2Error;
    }
    if (null_arg(m, "fmi2SetContinuousStates", "x", x, nx)) return fmi2Error;
    for (i = 0; i < nx; i++) {
        if (!isfinite(x[i])) {
            gbx_log(m, fmi2Error, "logStatusError", "fmi2SetContinuousStates: x[%u] = %g is not finite",
                    (unsigned)i, x[i]);
            return fmi2Error;
        }
    }
    for (i = 0; i < nx; i++) m->x[i] = x[i];
    return fmi2OK;
}

fmi2Status GBX2(GetDerivatives)(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    ModelInstance *m = (ModelInstance *)c;
    size_t i;
    if (not_allowed(m, "fmi2GetDerivatives", MASK_INIT | MASK_EVENT | MASK_CONT | MASK_TERMINATED | MASK_ERROR))
        return fmi2Error;
    if (nx != GBX_NX) {
        gbx_log(m, fmi2Error, "logStatusError", "fmi2GetDerivatives: nx = %u, expected %d", (unsigned)nx,
                GBX_NX);
        return fmi2Error;
    }
    if (null_arg(m, "fmi2GetDerivatives", "derivatives", derivatives, nx)) return fmi2Error;
    if (refresh_initial_state(m, "fmi2GetDerivatives") != 0) return fmi2Error;
    gbx_model_derivatives(m, m->time, m->x, derivatives);
    m->n_rhs++;
    for (i = 0; i < nx; i++) {
        if (!isfinite(derivatives[i])) {
            gbx_log(m, fmi2Error, "logStatusError", "fmi2GetDerivatives: derivative %u is not finite at t = %g",
                    (unsigned)i, m->time);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

fmi2Status GBX2(GetEventIndicators)(fmi2Component c, fmi2Real ei[], size_t ni) {
    ModelInstance *m = (ModelInstance *)c;
    (void)ei;
    if (not_allowed(m, "fmi2GetEventIndicators", MASK_ANY)) return fmi2Error;
    if (ni != 0) {
        gbx_log(m, fmi2Error, "logStatusError", "fmi2GetEventIndicators: ni = %u, the model has none",
                (unsigned)ni);
        return fmi2Error;
    }
    return fmi2OK;
}

fmi2Status GBX2(GetContinuousStates)(fmi2Component c, fmi2Real x[], size_t nx) {
    ModelInstance *m = (ModelInstance *)c;
    size_t i;
    if (not_allowed(m, "fmi2GetContinuousStates", MASK_INIT | MASK_EVENT | MASK_CONT | MASK_TERMINATED | MASK_ERROR))
        return fmi2Error;
    if (nx != GBX_NX) {
        gbx_log(m, fmi2Error, "logStatusError", "fmi2GetContinuousStates: nx = %u, expected %d",
                (unsigned)nx, GBX_NX);
        return fmi2Error;
    }
    if (null_arg(m, "fmi2GetContinuousStates", "x", x, nx)) return fmi2Error;
    if (refresh_initial_state(m, "fmi2GetContinuousStates") != 0) return fmi2Error;
    for (i = 0; i < nx; i++) x[i] = m->x[i];
    return fmi2OK;
}

fmi2Status GBX2(GetNominalsOfContinuousStates)(fmi2Component c, fmi2Real nominals[], size_t nx) {
    ModelInstance *m = (ModelInstance *)c;
    int i;
    if (not_allowed(m, "fmi2GetNominalsOfContinuousStates", MASK_ANY)) return fmi2Error;
    if (nx != GBX_NX) {
        gbx_log(m, fmi2Error, "logStatusError", "fmi2GetNominalsOfContinuousStates: nx = %u, expected %d",
                (unsigned)nx, GBX_NX);
        return fmi2Error;
    }
    if (null_arg(m, "fmi2GetNominalsOfContinuousStates", "nominals", nominals, nx)) return fmi2Error;
    for (i = 0; i < GBX_NR; i++)
        if (GBX_VARS[i].kind == GBX_STATE) nominals[GBX_VARS[i].index] = GBX_VARS[i].nominal;
    return fmi2OK;
}

/* ------------------------------------------------------- Co-Simulation: DOPRI5 */

/* Dormand-Prince 5(4) coefficients, Hairer-Norsett-Wanner I, Table 5.2 (Sec. II.5). */
static const double C2 = 1.0 / 5, C3 = 3.0 / 10, C4 = 4.0 / 5, C5 = 8.0 / 9;
static const double A21 = 1.0 / 5;
static const double A31 = 3.0 / 40, A32 = 9.0 / 40;
static const double A41 = 44.0 / 45, A42 = -56.0 / 15, A43 = 32.0 / 9;
static const double A51 = 19372.0 / 6561, A52 = -25360.0 / 2187, A53 = 64448.0 / 6561,
                    A54 = -212.0 / 729;
static const double A61 = 9017.0 / 3168, A62 = -355.0 / 33, A63 = 46732.0 / 5247, A64 = 49.0 / 176,
                    A65 = -5103.0 / 18656;
static const double A71 = 35.0 / 384, A73 = 500.0 / 1113, A74 = 125.0 / 192, A75 = -2187.0 / 6784,
                    A76 = 11.0 / 84;
/* error coefficients b - b_hat */
static const double E1 = 71.0 / 57600, E3 = -71.0 / 16695, E4 = 71.0 / 1920, E5 = -17253.0 / 339200,
                    E6 = 22.0 / 525, E7 = -1.0 / 40;

static void rhs(ModelInstance *m, double t, const double *x, double *dx) {
    gbx_model_derivatives(m, t, x, dx);
    m->n_rhs++;
}

/* min and max of finite numbers, inline (fmin and fmax are library calls at -O3) */
static inline double min2(double a, double b) { return a < b ? a : b; }
static inline double max2(double a, double b) { return a > b ? a : b; }

/* Integrate m->x from m->time to t1 with adaptive DOPRI5 steps at tolerance rtol; 0 on
 * success. */
static int integrate(ModelInstance *m, double t1, double rtol) {
    const int n = GBX_NX;
    double hmax = m->r[GBX_VR_SOLVER_MAX_STEP];
    double atol[GBX_NX_ALLOC];
    double t = m->time, h = m->h;
    double (*k)[GBX_NX_ALLOC] = m->k;
    double *xs = m->xs, *xn = m->xn, *x = m->x;
    long count = 0;
    int i, last_rejected = 0;
    double log_err_old = -9.210340371976182; /* log(1e-4) */
    if (n == 0) {
        m->time = t1;
        return 0;
    }
    for (i = 0; i < GBX_NR; i++)
        if (GBX_VARS[i].kind == GBX_STATE) atol[GBX_VARS[i].index] = rtol * GBX_VARS[i].nominal;
    if (!(h > 0.0)) h = min2(hmax, 1e-6);
    double h_try = h;
    if (!m->fsal_valid) rhs(m, t, x, k[0]); /* else k[0] = f(t, x) from the last step */
    while (t < t1) {
        double err = 0.0, fac;
        int final;
        if (++count > GBX_MAX_SUBSTEPS) {
            gbx_log(m, fmi2Error, "logStatusError",
                    "fmi2DoStep: more than %ld internal steps between t = %g and %g s", GBX_MAX_SUBSTEPS,
                    m->time, t1);
            return 1;
        }
        h = min2(h, hmax);
        h_try = h;
        final = t + h >= t1 - 1e-12 * fabs(t1);
        if (final) h = t1 - t; /* land on the communication point */
        if (!(h > 1e-14 * max2(1.0, fabs(t)))) {
            gbx_log(m, fmi2Error, "logStatusError", "fmi2DoStep: step size underflow (h = %g s) at t = %g s",
                    h, t);
            return 1;
        }
        for (i = 0; i < n; i++) xs[i] = x[i] + h * A21 * k[0][i];
        rhs(m, t + C2 * h, xs, k[1]);
        for (i = 0; i < n; i++) xs[i] = x[i] + h * (A31 * k[0][i] + A32 * k[1][i]);
        rhs(m, t + C3 * h, xs, k[2]);
        for (i = 0; i < n; i++) xs[i] = x[i] + h * (A41 * k[0][i] + A42 * k[1][i] + A43 * k[2][i]);
        rhs(m, t + C4 * h, xs, k[3]);
        for (i = 0; i < n; i++)
            xs[i] = x[i] + h * (A51 * k[0][i] + A52 * k[1][i] + A53 * k[2][i] + A54 * k[3][i]);
        rhs(m, t + C5 * h, xs, k[4]);
        for (i = 0; i < n; i++)
            xs[i] = x[i] + h * (A61 * k[0][i] + A62 * k[1][i] + A63 * k[2][i] + A64 * k[3][i] +
                                A65 * k[4][i]);
        rhs(m, t + h, xs, k[5]);
        for (i = 0; i < n; i++)
            xn[i] = x[i] + h * (A71 * k[0][i] + A73 * k[2][i] + A74 * k[3][i] + A75 * k[4][i] +
                                A76 * k[5][i]);
        rhs(m, t + h, xn, k[6]);
        for (i = 0; i < n; i++) {
            double e = h * (E1 * k[0][i] + E3 * k[2][i] + E4 * k[3][i] + E5 * k[4][i] + E6 * k[5][i] +
                            E7 * k[6][i]);
            double a = fabs(x[i]), b = fabs(xn[i]);
            double sc = atol[i] + rtol * (a > b ? a : b);
            err += (e / sc) * (e / sc);
        }
        err = sqrt(err / n); /* HNW I eq. (4.11) */
        if (!isfinite(err)) err = 1e10;
        if (err <= 1.0) {
            double log_err = log(err > 1e-10 ? err : 1e-10);
            t = final ? t1 : t + h;
            for (i = 0; i < n; i++) {
                x[i] = xn[i];
                k[0][i] = k[6][i]; /* first same as last */
            }
            m->n_steps++;
            /* PI step control with Lund stabilisation, beta = 0.04 (HNW I, Sec. II.4 and
             * the DOPRI5 code of Hairer and Wanner): fewer rejected steps on
             * oscillatory solutions than the plain err^(-1/5) rule;
             * fac = err^(0.2 - 0.75 beta) / err_old^beta / 0.9 */
            fac = exp((0.2 - 0.04 * 0.75) * log_err - 0.04 * log_err_old) / 0.9;
            fac = min2(5.0, max2(0.1, fac)); /* h_new = h / fac in [h/5, 10 h] */
            if (last_rejected) fac = max2(fac, 1.0);
            log_err_old = log_err > -9.210340371976182 ? log_err : -9.210340371976182; /* 1e-4 */
            /* after the step cut short at the communication point, go on with the step
             * the controller had chosen, not with the cut one */
            h = final ? (fac > 1.0 ? min2(h_try, h / fac) : h_try) : h / fac;
            last_rejected = 0;
        } else {
            m->n_rejected++;
            h /= min2(5.0, pow(err, 0.2 - 0.04 * 0.75) / 0.9);
            last_rejected = 1;
        }
    }
    for (i = 0; i < n; i++) {
        if (!isfinite(x[i])) {
            gbx_log(m, fmi2Error, "logStatusError", "fmi2DoStep: state %d is not finite at t = %g s", i, t);
            return 1;
        }
    }
    m->h = h;
    m->fsal_valid = 1;
    m->time = t1;
    return 0;
}

/* ---------------------------------------------- Co-Simulation: fixed-step Tsit5 */

/* Tsitouras 5(4) coefficients (Tsitouras 2011, Table 1; the tableau of diffrax.Tsit5),
 * without the last stage, which serves only the error estimate. */
#define TS_S 6
static const double TS_C[TS_S] = {0.0, 0.161, 0.327, 0.9, 0.9800255409045097, 1.0};
static const double TS_A[TS_S][TS_S] = {
    {0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    {0.161, 0.0, 0.0, 0.0, 0.0, 0.0},
    {-0.008480655492356989, 0.335480655492357, 0.0, 0.0, 0.0, 0.0},
    {2.8971530571054935, -6.359448489975075, 4.3622954328695815, 0.0, 0.0, 0.0},
    {5.325864828439257, -11.748883564062828, 7.4955393428898365, -0.09249506636175525, 0.0, 0.0},
    {5.86145544294642, -12.92096931784711, 8.159367898576159, -0.071584973281401,
     -0.028269050394068383, 0.0}};
static const double TS_B[TS_S] = {0.09646076681806523, 0.01,
                                  0.4798896504144996,  1.379008574103742,
                                  -3.290069515436081,  2.324710524099774};
/* accepted growth per step, gearbox.drivetrain.linear.STEP_GROWTH */
#define TS_GROWTH 1e-8

/* complex numbers without <complex.h> (not every C compiler of the importers has it) */
typedef struct {
    double re, im;
} cplx;
static cplx cx(double re, double im) {
    cplx z;
    z.re = re;
    z.im = im;
    return z;
}
static cplx cadd(cplx a, cplx b) { return cx(a.re + b.re, a.im + b.im); }
static cplx csub(cplx a, cplx b) { return cx(a.re - b.re, a.im - b.im); }
static cplx cmul(cplx a, cplx b) { return cx(a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re); }
static cplx cconj(cplx a) { return cx(a.re, -a.im); }
static cplx cscale(cplx a, double s) { return cx(a.re * s, a.im * s); }
static double cabs2(cplx a) { return hypot(a.re, a.im); }
static cplx csqrt2(cplx a) {
    double r = cabs2(a), re = sqrt(0.5 * (r + a.re)), im = sqrt(0.5 * fmax(r - a.re, 0.0));
    return cx(re, a.im < 0.0 ? -im : im);
}

/* Eigenvalues of the real n x n matrix A (row-major, n <= GBX_NX; A is overwritten):
 * Householder reduction to Hessenberg form, then shifted QR iterations in complex
 * arithmetic (Wilkinson shift, Givens rotations, deflation at negligible subdiagonal
 * entries; Golub and Van Loan, Matrix Computations, 4th ed., Sec. 7.4-7.5). Returns the
 * number of eigenvalues found (n, or fewer when the iteration did not converge). */
static int eigenvalues(int n, double *A, cplx *lam) {
    cplx H[GBX_NX_ALLOC][GBX_NX_ALLOC];
    double v[GBX_NX_ALLOC];
    int i, j, k, hi, iter = 0;
    for (k = 0; k + 2 < n; k++) {
        double alpha = 0.0, vv = 0.0;
        for (i = k + 1; i < n; i++) alpha += A[i * n + k] * A[i * n + k];
        alpha = sqrt(alpha);
        if (alpha == 0.0) continue;
        if (A[(k + 1) * n + k] > 0.0) alpha = -alpha;
        for (i = 0; i < n; i++) v[i] = i <= k ? 0.0 : A[i * n + k];
        v[k + 1] -= alpha;
        for (i = k + 1; i < n; i++) vv += v[i] * v[i];
        if (vv == 0.0) continue;
        for (j = 0; j < n; j++) { /* A = (I - 2 v v' / v'v) A */
            double f = 0.0;
            for (i = k + 1; i < n; i++) f += v[i] * A[i * n + j];
            f *= 2.0 / vv;
            for (i = k + 1; i < n; i++) A[i * n + j] -= f * v[i];
        }
        for (i = 0; i < n; i++) { /* A = A (I - 2 v v' / v'v) */
            double f = 0.0;
            for (j = k + 1; j < n; j++) f += A[i * n + j] * v[j];
            f *= 2.0 / vv;
            for (j = k + 1; j < n; j++) A[i * n + j] -= f * v[j];
        }
    }
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) H[i][j] = cx(j + 1 >= i ? A[i * n + j] : 0.0, 0.0);
    hi = n - 1;
    while (hi >= 0) {
        int l;
        cplx mu;
        if (iter > 100 * n) return n - 1 - hi;
        for (l = hi; l > 0; l--) {
            if (cabs2(H[l][l - 1]) <= 1e-16 * (cabs2(H[l - 1][l - 1]) + cabs2(H[l][l]))) {
                H[l][l - 1] = cx(0.0, 0.0);
                break;
            }
        }
        if (l == hi) {
            lam[hi--] = H[l][l];
            iter = 0;
            continue;
        }
        { /* Wilkinson shift: the eigenvalue of the trailing 2 x 2 block nearer H[hi][hi] */
            cplx a = H[hi - 1][hi - 1], b = H[hi - 1][hi], c = H[hi][hi - 1], d = H[hi][hi];
            cplx half = cscale(csub(a, d), 0.5);
            cplx disc = csqrt2(cadd(cmul(half, half), cmul(b, c)));
            cplx m1 = cadd(cscale(cadd(a, d), 0.5), disc), m2 = csub(cscale(cadd(a, d), 0.5), disc);
            mu = cabs2(csub(m1, d)) < cabs2(csub(m2, d)) ? m1 : m2;
            if (iter % 10 == 9) mu = cadd(d, cx(cabs2(c), 0.0)); /* exceptional shift */
        }
        {
            cplx g[GBX_NX_ALLOC][2];
            for (k = l; k <= hi; k++) H[k][k] = csub(H[k][k], mu);
            for (k = l; k < hi; k++) { /* H = G_k H: zero H[k+1][k] */
                cplx x = H[k][k], y = H[k + 1][k];
                double r = hypot(cabs2(x), cabs2(y));
                if (r == 0.0) {
                    g[k][0] = cx(1.0, 0.0);
                    g[k][1] = cx(0.0, 0.0);
                    continue;
                }
                g[k][0] = cscale(x, 1.0 / r);
                g[k][1] = cscale(y, 1.0 / r);
                for (j = k; j <= hi; j++) {
                    cplx p = H[k][j], q = H[k + 1][j];
                    H[k][j] = cadd(cmul(cconj(g[k][0]), p), cmul(cconj(g[k][1]), q));
                    H[k + 1][j] = csub(cmul(g[k][0], q), cmul(g[k][1], p));
                }
            }
            for (k = l; k < hi; k++) { /* H = H G_k^H */
                int top = k + 2 < hi ? k + 2 : hi;
                for (i = l; i <= top; i++) {
                    cplx p = H[i][k], q = H[i][k + 1];
                    H[i][k] = cadd(cmul(p, g[k][0]), cmul(q, g[k][1]));
                    H[i][k + 1] = csub(cmul(q, cconj(g[k][0])), cmul(p, cconj(g[k][1])));
                }
            }
            for (k = l; k <= hi; k++) H[k][k] = cadd(H[k][k], mu);
        }
        iter++;
    }
    return n;
}

/* |R(z)| of Tsit5's stability polynomial R(z) = sum_k r_k z^k, r_k = b' A^(k-1) 1 */
static double stability_abs(const double *r, cplx z) {
    cplx p = cx(r[TS_S], 0.0);
    int k;
    for (k = TS_S - 1; k >= 0; k--) p = cadd(cmul(p, z), cx(r[k], 0.0));
    return cabs2(p);
}

static int stable_step(const double *r, int n, const cplx *lam, double h) {
    int j;
    for (j = 0; j < n; j++)
        if (cabs2(lam[j]) > 0.0 && stability_abs(r, cscale(lam[j], h)) > 1.0 + TS_GROWTH) return 0;
    return 1;
}

/* The step of the fixed-step integrator from the parameters (after gbx_model_update):
 * gearbox.drivetrain.fixed_step.step_targets with gearbox.drivetrain.linear.
 * largest_stable_step (a scan over (0, 6 / max|lambda|] in 240 steps, then 50
 * bisections), and at most 1 / (solver.steps_per_mesh_period f_mesh) (f_mesh: the
 * model's forcing frequency), the cap the Python default gets from its 32 samples per
 * mesh period. 0 ok; 1 with a message when an explicit solver.fixed_step exceeds the
 * stability limit in Co-Simulation with solver.method = 1. */
static int fixed_step_rule(ModelInstance *m, char *msg, size_t nmsg) {
    const int n = GBX_NX;
    double A[GBX_NX_ALLOC * GBX_NX_ALLOC], r[TS_S + 1], v[TS_S], w[TS_S];
    double top = 0.0, fforce, lo, up, hi, spp = m->r[GBX_VR_SOLVER_STEPS_PER_PERIOD];
    double hset = m->r[GBX_VR_SOLVER_FIXED_STEP], spf = m->r[GBX_VR_SOLVER_STEPS_PER_FORCING];
    cplx lam[GBX_NX_ALLOC];
    int i, j, k, ne;
    for (i = 0; i < TS_S; i++) v[i] = 1.0;
    r[0] = 1.0;
    for (k = 1; k <= TS_S; k++) { /* r_k = b' v, v = A v */
        r[k] = 0.0;
        for (i = 0; i < TS_S; i++) r[k] += TS_B[i] * v[i];
        for (i = 0; i < TS_S; i++) {
            w[i] = 0.0;
            for (j = 0; j < i; j++) w[i] += TS_A[i][j] * v[j];
        }
        memcpy(v, w, sizeof v);
    }
    fforce = n > 0 ? gbx_model_linear(m, A) : 0.0;
    ne = n > 0 ? eigenvalues(n, A, lam) : 0;
    if (ne != n) {
        snprintf(msg, nmsg, "the eigenvalues of the linearised model did not converge");
        return 1;
    }
    for (j = 0; j < n; j++) top = fmax(top, cabs2(lam[j]));
    m->fs_fmax = fmax(top / TWO_PI_RT, fforce);
    if (top > 0.0) {
        hi = 6.0 / top;
        lo = 0.0;
        up = hi;
        for (k = 1; k <= 240; k++) {
            double h = hi * k / 240.0;
            if (!stable_step(r, n, lam, h)) {
                up = h;
                break;
            }
            lo = h;
        }
        if (k <= 240) {
            for (k = 0; k < 50; k++) {
                double mid = 0.5 * (lo + up);
                if (stable_step(r, n, lam, mid))
                    lo = mid;
                else
                    up = mid;
            }
            m->fs_limit = lo;
        } else {
            m->fs_limit = hi;
        }
    } else {
        m->fs_limit = HUGE_VAL;
    }
    if (hset > 0.0) {
        m->fs_step = hset;
        if (m->type == fmi2CoSimulation && m->r[GBX_VR_SOLVER_METHOD] == 1.0 && hset > m->fs_limit) {
            snprintf(msg, nmsg,
                     "solver.fixed_step = %g s is invalid: must be <= %.4g s (stability limit of the "
                     "fixed-step Tsit5 on the model linearised at peak mesh stiffness), or 0 for the "
                     "automatic step",
                     hset, m->fs_limit);
            return 1;
        }
    } else {
        m->fs_step = m->fs_fmax > 0.0 ? 1.0 / (spp * m->fs_fmax) : HUGE_VAL;
        if (fforce > 0.0) m->fs_step = min2(m->fs_step, 1.0 / (spf * fforce));
        if (m->fs_step > 0.8 * m->fs_limit) m->fs_step = 0.8 * m->fs_limit;
    }
    return 0;
}

/* One Tsit5 step of size h from (t, x) to xn (m->k as stage storage). */
static void tsit5_step(ModelInstance *m, double t, double h, const double *x, double *xn) {
    const int n = GBX_NX;
    double (*k)[GBX_NX_ALLOC] = m->k;
    double *xs = m->xs;
    int i, s, j;
    rhs(m, t, x, k[0]);
    for (s = 1; s < TS_S; s++) {
        for (i = 0; i < n; i++) {
            double a = 0.0;
            for (j = 0; j < s; j++) a += TS_A[s][j] * k[j][i];
            xs[i] = x[i] + h * a;
        }
        rhs(m, t + TS_C[s] * h, xs, k[s]);
    }
    for (i = 0; i < n; i++) {
        double a = 0.0;
        for (j = 0; j < TS_S; j++) a += TS_B[j] * k[j][i];
        xn[i] = x[i] + h * a;
    }
}

/* Integrate m->x from m->time to t1 with ceil((t1 - t) / step) equal Tsit5 steps (step
 * = m->fs_step, at most solver.max_step). A step that ends out of the nominal contact is
 * discarded and its interval integrated with adaptive DOPRI5 steps at
 * solver.contact_rtol, as are the following intervals until a step ends in contact
 * again. 0 on success. */
static int integrate_fixed(ModelInstance *m, double t1) {
    const int n = GBX_NX;
    const double t0 = m->time, span = t1 - t0;
    double hmax = min2(m->fs_step, m->r[GBX_VR_SOLVER_MAX_STEP]), h, ns_d;
    double *x = m->x, xn[GBX_NX_ALLOC];
    long ns, j;
    int i;
    if (n == 0) {
        m->time = t1;
        return 0;
    }
    ns_d = ceil(span / hmax * (1.0 - 1e-12));
    if (!(ns_d <= (double)GBX_MAX_SUBSTEPS)) {
        gbx_log(m, fmi2Error, "logStatusError",
                "fmi2DoStep: more than %ld internal steps between t = %g and %g s", GBX_MAX_SUBSTEPS,
                t0, t1);
        return 1;
    }
    ns = ns_d < 1.0 ? 1 : (long)ns_d;
    h = span / ns;
    for (j = 0; j < ns; j++) {
        double ta = t0 + j * h, tb = j + 1 == ns ? t1 : t0 + (j + 1) * h;
        if (!m->out_of_contact) {
            tsit5_step(m, ta, tb - ta, x, xn);
            if (gbx_model_in_contact(m, tb, xn)) {
                for (i = 0; i < n; i++) x[i] = xn[i];
                m->n_steps++;
                continue;
            }
        }
        /* contact lost (impact or separation): adaptive steps over [ta, tb] */
        m->n_handed_over++;
        m->time = ta;
        m->fsal_valid = 0;
        if (m->h > tb - ta || !(m->h > 0.0)) m->h = 0.25 * (tb - ta);
        if (integrate(m, tb, m->r[GBX_VR_SOLVER_CONTACT_RTOL]) != 0) return 1;
        m->out_of_contact = !gbx_model_in_contact(m, tb, x);
    }
    m->fsal_valid = 0;
    for (i = 0; i < n; i++) {
        if (!isfinite(x[i])) {
            gbx_log(m, fmi2Error, "logStatusError", "fmi2DoStep: state %d is not finite at t = %g s", i,
                    t1);
            return 1;
        }
    }
    m->time = t1;
    return 0;
}

fmi2Status GBX2(SetRealInputDerivatives)(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    UNSUPPORTED("fmi2SetRealInputDerivatives")
}

fmi2Status GBX2(GetRealOutputDerivatives)(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    UNSUPPORTED("fmi2GetRealOutputDerivatives")
}

fmi2Status GBX2(DoStep)(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    ModelInstance *m = (ModelInstance *)c;
    double t1;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (not_allowed(m, "fmi2DoStep", MASK_STEP)) return fmi2Error;
    if (!(communicationStepSize > 0.0) || !isfinite(communicationStepSize)) {
        gbx_log(m, fmi2Error, "logStatusError", "fmi2DoStep: communicationStepSize = %g must be > 0",
                communicationStepSize);
        return fmi2Error;
    }
    if (fabs(currentCommunicationPoint - m->time) > 1e-9 * fmax(1.0, fabs(m->time))) {
        gbx_log(m, fmi2Error, "logStatusError",
                "fmi2DoStep: currentCommunicationPoint = %.17g s, but the FMU is at t = %.17g s",
                currentCommunicationPoint, m->time);
        return fmi2Error;
    }
    m->time = currentCommunicationPoint;
    t1 = currentCommunicationPoint + communicationStepSize;
    if ((m->r[GBX_VR_SOLVER_METHOD] == 1.0 ? integrate_fixed(m, t1)
                                           : integrate(m, t1, m->r[GBX_VR_SOLVER_RTOL])) != 0) {
        m->state = GBX_ST_ERROR;
        return fmi2Error;
    }
    return fmi2OK;
}

fmi2Status GBX2(CancelStep)(fmi2Component c) UNSUPPORTED("fmi2CancelStep")

fmi2Status GBX2(GetStatus)(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)s;
    (void)value;
    UNSUPPORTED("fmi2GetStatus")
}
fmi2Status GBX2(GetRealStatus)(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    ModelInstance *m = (ModelInstance *)c;
    if (not_allowed(m, "fmi2GetRealStatus", MASK_ANY)) return fmi2Error;
    if (s == fmi2LastSuccessfulTime && value) {
        *value = m->time;
        return fmi2OK;
    }
    gbx_log(m, fmi2Error, "logStatusError", "fmi2GetRealStatus: only fmi2LastSuccessfulTime is supported");
    return fmi2Error;
}
fmi2Status GBX2(GetIntegerStatus)(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)s;
    (void)value;
    UNSUPPORTED("fmi2GetIntegerStatus")
}
fmi2Status GBX2(GetBooleanStatus)(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    (void)s;
    (void)value;
    UNSUPPORTED("fmi2GetBooleanStatus")
}
fmi2Status GBX2(GetStringStatus)(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)s;
    (void)value;
    UNSUPPORTED("fmi2GetStringStatus")
}
