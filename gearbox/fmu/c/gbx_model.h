/* gbx_model.h: the interface between the generic FMI 2.0 runtime (fmi2_runtime.c)
 * and one generated model (model.c + config.h).
 *
 * The runtime owns the FMI state machine, argument checks, logging, memory, the
 * resource folder and the internal Co-Simulation integrator; the model owns its
 * equations and its tables. Every real variable has a value reference (vr) that is
 * its index into ModelInstance.r; states and their derivatives live in x and dx and
 * are addressed through GBX_VARS[vr].index.
 */
#ifndef GBX_MODEL_H
#define GBX_MODEL_H

#include <stddef.h>

#include "config.h"
#include "fmi2Functions.h"

typedef enum {
    GBX_PARAMETER = 0, /* tunable parameter (checked against min/max when set) */
    GBX_INPUT = 1,     /* continuous input */
    GBX_OUTPUT = 2,    /* continuous output, computed from states and inputs */
    GBX_STATE = 3,     /* continuous state (local, initial="calculated") */
    GBX_DERIVATIVE = 4 /* derivative of a state */
} gbx_kind;

typedef struct {
    const char *name;
    gbx_kind kind;
    int index;    /* state/derivative: index into x; input: vr of its rate input or -1 */
    double start; /* start value (parameters, inputs) */
    double min, max;
    int min_open, max_open; /* 1: the bound itself is not allowed */
    double nominal;         /* states: scale of the absolute tolerance */
    int fixed;              /* parameters: 1 = settable only before initialization ends */
} gbx_var;

/* Generated in model.c, one entry per value reference. */
extern const gbx_var GBX_VARS[GBX_NR];

typedef enum {
    GBX_ST_INSTANTIATED,
    GBX_ST_INIT,
    GBX_ST_EVENT,
    GBX_ST_CONT,
    GBX_ST_STEP,
    GBX_ST_TERMINATED,
    GBX_ST_ERROR
} gbx_state;

#define GBX_NX_ALLOC (GBX_NX > 0 ? GBX_NX : 1)

typedef struct ModelInstance {
    char *name;
    char *resource_dir; /* local path of the FMU's resources/ folder, no trailing slash */
    fmi2CallbackFunctions cb;
    int logging;
    fmi2Type type;
    gbx_state state;
    double time;
    double t_input;  /* time at which the inputs were last set (CS extrapolation origin) */
    int x_pending;   /* initial state must be (re)computed from the parameters */
    double r[GBX_NR];
    double x[GBX_NX_ALLOC];
    GbxModelData data; /* model tables (config.h) */
    /* internal integrator (DOPRI5) workspace and work counters */
    double h;
    int fsal_valid; /* k[0] holds f(time, x): no input or parameter changed since */
    double k[7][GBX_NX_ALLOC];
    double xs[GBX_NX_ALLOC];
    double xn[GBX_NX_ALLOC];
    long n_steps, n_rejected, n_rhs;
    /* fixed-step Tsit5 (solver.method = 1): step rule evaluated at every parameter
     * update (fmi2_runtime.c, fixed_step_rule) */
    double fs_step;  /* step in use (s): solver.fixed_step, or the automatic rule */
    double fs_limit; /* stability limit of Tsit5 on the linearised model (s) */
    double fs_fmax;  /* highest frequency the automatic step resolves (Hz) */
    int out_of_contact; /* the last step ended out of the nominal contact */
    long n_handed_over; /* fixed-step intervals integrated with adaptive steps */
} ModelInstance;

/* ---- implemented by the generated model.c ---- */
/* Read the model's tables from m->resource_dir; return 0, or nonzero after logging. */
int gbx_model_load(ModelInstance *m);
/* Release what gbx_model_load allocated (safe on a partly loaded model). */
void gbx_model_free(ModelInstance *m);
/* Check the parameters against each other and the tables and recompute the derived
 * constants (m->data); 0 ok, else a message in msg. Called after every parameter
 * change and before the initial state is computed. */
int gbx_model_update(ModelInstance *m, char *msg, size_t n);
/* Initial state from the parameters at m->time. */
void gbx_model_initial_state(ModelInstance *m);
/* dx/dt at (t, x). */
void gbx_model_derivatives(const ModelInstance *m, double t, const double *x, double *dx);
/* Fill the output variables of m->r at (t, x). */
void gbx_model_outputs(ModelInstance *m, double t, const double *x);
/* The state equations linearised at the operating point with every mesh at its largest
 * stiffness: A (GBX_NX x GBX_NX, row-major) with d(dx)/dt = A dx; returns the highest
 * forcing frequency (Hz) the fixed step must resolve besides the eigenfrequencies.
 * Called after gbx_model_update succeeded. */
double gbx_model_linear(const ModelInstance *m, double *A);
/* 1 while (t, x) lies in the nominal contact (drive flank closed, coast flank open):
 * a fixed step that ends elsewhere has crossed a kink of the right-hand side. */
int gbx_model_in_contact(const ModelInstance *m, double t, const double *x);

/* ---- services of the runtime ---- */
void gbx_log(const ModelInstance *m, fmi2Status status, const char *category, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
/* Value of input vr at time t; in Co-Simulation extrapolated linearly over the
 * communication step with its rate input (an angle with its speed). Inline: the
 * right-hand side reads inputs at every evaluation. */
static inline double gbx_input(const ModelInstance *m, int vr, double t) {
    int rate = GBX_VARS[vr].index;
    double u = m->r[vr];
    if (m->type == fmi2CoSimulation && rate >= 0) u += m->r[rate] * (t - m->t_input);
    return u;
}
void *gbx_calloc(const ModelInstance *m, size_t n, size_t size);
void gbx_free(const ModelInstance *m, void *p);
/* Read a numeric table "<resource_dir>/<file>": a header line
 * "gearbox-table 1 <rows> <cols>", '#' comment lines, then rows*cols numbers.
 * On success *data holds rows*cols values (row-major), allocated with gbx_calloc. */
int gbx_read_table(ModelInstance *m, const char *file, int *rows, int *cols, double **data);

#endif /* GBX_MODEL_H */
