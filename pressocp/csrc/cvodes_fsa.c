/* Forward sensitivities of an explicit ODE x' = f(t, x, p) through CVODES, with a dense direct linear
 * solver: through CVODES's own sensitivity module (staggered corrector, sensitivities under the error
 * control), or with the directions integrated as states (NB > 1, below).
 *
 * Compiled by pressocp.cvodes_fsa together with CasADi-generated code of the model, which defines
 *   f_ode(t, x, p) -> f                      (NX)
 *   f_jac(t, x, p) -> df/dx                  (NX x NX, dense, column major)
 *   f_jfull(t, x, p) -> df/d[x; q]           (NX x (NX + NQ), dense, column major)
 * with q the last NQ entries of p, and the macros NX, NQ, SZ_ARG, SZ_RES, SZ_IW, SZ_W (the largest work
 * sizes of the three). Linked against CasADi's libcasadi_integrator_cvodes, which exports CVODES 2.6.1.
 *
 * With NB > 1 blocks of NXB states (NX = NB * NXB, NQ = 0), the state is a model's NXB states followed by
 * NB - 1 directions integrated with them as one system: f_jac is then the model's NXB x NXB Jacobian and
 * the Newton solve applies its factorisation to every block (the block-diagonal Newton matrix of
 * CVODES's simultaneous corrector), with CVODES's vector operations on one vector instead of NB.
 *
 * The sensitivity right-hand side f_x S + f_q Q is evaluated from one Jacobian per (t, x): the staggered
 * corrector iterates the sensitivities at a fixed state, so the Jacobian is reused across its
 * iterations and directions. The linear solver follows CVODES's dense one (CVDense): the Jacobian is
 * recomputed on a bad convergence or every 50 steps, and the solution is scaled by 2 / (1 + gamrat)
 * when gamma has changed since the factorisation.
 */
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include <cvodes/cvodes.h>
#include <cvodes/cvodes_impl.h>
#include <nvector/nvector_serial.h>

#ifndef NB
#define NB 1
#define NXB NX
#endif

typedef struct {
  const double *p;   /* all parameters */
  const double *Q;   /* NQ x ns, column major: the parameter directions */
  double jac[NXB * NXB];
  double lu[NXB * NXB];
  double inv[NXB * NXB]; /* (I - gamma J)^-1, row major */
  int piv[NXB];
  double jfull[NXB * (NXB + NQ)];
  double tc, xc[NX];
  int have_jfull;
  long nstlj, njac, njfull;
  const volatile int *stop; /* the caller's stop request (may be NULL) */
  const casadi_real *arg[SZ_ARG];
  casadi_real *res[SZ_RES];
  casadi_int iw[SZ_IW + 1];
  casadi_real w[SZ_W + 1];
} Mem;

/* Set by a SIGINT during a run that asked to catch it: the right-hand side then fails, which ends the run. */
static volatile sig_atomic_t interrupted = 0;

static void on_sigint(int signum) { interrupted = 1; }

static int rhs(realtype t, N_Vector x, N_Vector xdot, void *user_data) {
  Mem *m = (Mem *)user_data;
  if (interrupted || (m->stop && *m->stop)) return -1;
  m->arg[0] = &t;
  m->arg[1] = NV_DATA_S(x);
  m->arg[2] = m->p;
  m->res[0] = NV_DATA_S(xdot);
  return f_ode(m->arg, m->res, m->iw, m->w, 0) ? -1 : 0;
}

/* LU with partial pivoting of I - gamma J, then its inverse (NXB is small: a product per solve) */
static int factorise(Mem *m, double gamma) {
  int i, j, k, c;
  double *a = m->lu;
  for (k = 0; k < NXB * NXB; ++k) a[k] = -gamma * m->jac[k];
  for (k = 0; k < NXB; ++k) a[k * NXB + k] += 1.0;
  for (k = 0; k < NXB; ++k) { /* a(i, j) = a[j * NXB + i] */
    int p = k;
    double amax = fabs(a[k * NXB + k]);
    for (i = k + 1; i < NXB; ++i)
      if (fabs(a[k * NXB + i]) > amax) {
        amax = fabs(a[k * NXB + i]);
        p = i;
      }
    m->piv[k] = p;
    if (amax == 0.0) return 1;
    if (p != k)
      for (j = 0; j < NXB; ++j) {
        double s = a[j * NXB + k];
        a[j * NXB + k] = a[j * NXB + p];
        a[j * NXB + p] = s;
      }
    for (i = k + 1; i < NXB; ++i) a[k * NXB + i] /= a[k * NXB + k];
    for (j = k + 1; j < NXB; ++j) {
      double s = a[j * NXB + k];
      if (s != 0.0)
        for (i = k + 1; i < NXB; ++i) a[j * NXB + i] -= a[k * NXB + i] * s;
    }
  }
  for (c = 0; c < NXB; ++c) { /* column c of the inverse */
    double b[NXB];
    for (k = 0; k < NXB; ++k) b[k] = (k == c);
    for (k = 0; k < NXB; ++k) {
      int p = m->piv[k];
      if (p != k) {
        double s = b[k];
        b[k] = b[p];
        b[p] = s;
      }
    }
    for (k = 0; k < NXB; ++k)
      for (i = k + 1; i < NXB; ++i) b[i] -= a[k * NXB + i] * b[k];
    for (k = NXB - 1; k >= 0; --k) {
      b[k] /= a[k * NXB + k];
      for (i = 0; i < k; ++i) b[i] -= a[k * NXB + i] * b[k];
    }
    for (k = 0; k < NXB; ++k) m->inv[k * NXB + c] = b[k];
  }
  return 0;
}

static int lsetup(CVodeMem cv, int convfail, N_Vector xpred, N_Vector fpred, booleantype *jcur, N_Vector tmp1,
                  N_Vector tmp2, N_Vector tmp3) {
  Mem *m = (Mem *)cv->cv_lmem;
  double dgamma = fabs(cv->cv_gamma / cv->cv_gammap - 1.0);
  int jbad = cv->cv_nst == 0 || cv->cv_nst > m->nstlj + 50 || (convfail == CV_FAIL_BAD_J && dgamma < 0.2) ||
             convfail == CV_FAIL_OTHER;
  if (jbad) {
    double t = cv->cv_tn;
    m->arg[0] = &t;
    m->arg[1] = NV_DATA_S(xpred);
    m->arg[2] = m->p;
    m->res[0] = m->jac;
    if (f_jac(m->arg, m->res, m->iw, m->w, 0)) return -1;
    m->nstlj = cv->cv_nst;
    m->njac++;
    *jcur = TRUE;
  } else {
    *jcur = FALSE;
  }
  return factorise(m, cv->cv_gamma) ? 1 : 0;
}

static int lsolve(CVodeMem cv, N_Vector bv, N_Vector weight, N_Vector xcur, N_Vector fcur) {
  Mem *m = (Mem *)cv->cv_lmem;
  double r[NXB];
  double c = cv->cv_gamrat != 1.0 ? 2.0 / (1.0 + cv->cv_gamrat) : 1.0;
  int i, k, block;
  for (block = 0; block < NB; ++block) {
    double *b = NV_DATA_S(bv) + block * NXB;
    for (i = 0; i < NXB; ++i) {
      double s = 0.0;
      for (k = 0; k < NXB; ++k) s += m->inv[i * NXB + k] * b[k];
      r[i] = s;
    }
    for (i = 0; i < NXB; ++i) b[i] = c * r[i];
  }
  return 0;
}

static int sensitivity_rhs(int ns, realtype t, N_Vector x, N_Vector xdot, N_Vector *xS, N_Vector *xSdot,
                           void *user_data, N_Vector tmp1, N_Vector tmp2) {
  Mem *m = (Mem *)user_data;
  const double *xv = NV_DATA_S(x);
  int i, j, k;
  if (!m->have_jfull || t != m->tc || memcmp(xv, m->xc, NX * sizeof(double))) {
    m->arg[0] = &t;
    m->arg[1] = xv;
    m->arg[2] = m->p;
    m->res[0] = m->jfull;
    if (f_jfull(m->arg, m->res, m->iw, m->w, 0)) return -1;
    m->tc = t;
    memcpy(m->xc, xv, NX * sizeof(double));
    m->have_jfull = 1;
    m->njfull++;
  }
  for (j = 0; j < ns; ++j) {
    const double *s = NV_DATA_S(xS[j]), *q = m->Q + j * NQ;
    double *r = NV_DATA_S(xSdot[j]);
    for (i = 0; i < NX; ++i) r[i] = 0.0;
    for (k = 0; k < NX; ++k)
      if (s[k] != 0.0)
        for (i = 0; i < NX; ++i) r[i] += m->jfull[k * NX + i] * s[k];
    for (k = 0; k < NQ; ++k)
      if (q[k] != 0.0)
        for (i = 0; i < NX; ++i) r[i] += m->jfull[(NX + k) * NX + i] * q[k];
  }
  return 0;
}

static void quiet(int error_code, const char *module, const char *function, char *msg, void *eh_data) {}

/* Integrate from t = 0 and x0 with ns directions (initial values S0, NX x ns, and parameter directions
 * Q, NQ x ns, both column major) to each time of grid (increasing, > 0); write the states (NX x ngrid)
 * and the directions (NX x ns x ngrid). rtol and atol are the tolerances of the states; the
 * directions' are estimated from them (CVodeSensEEtolerances). stats: steps, right-hand sides, Jacobians of the linear solver, sensitivity
 * Jacobians, the time reached, and 1 when a SIGINT stopped the run (caught only with catch_sigint: the
 * caller's handler is restored afterwards). A run also stops when *stop (if stop is not NULL) becomes
 * nonzero: another thread's request. Returns 0 or CVODES's (negative) flag; -22 (CV_ILL_INPUT)
 * also when CVODES's memory does not have the layout of the headers this was compiled with. */
int fsa_run(const double *x0, const double *p, int ns, const double *S0, const double *Q, int ngrid,
            const double *grid, double rtol, double atol, long max_steps, int catch_sigint,
            const volatile int *stop, double *xout, double *Sout, double *stats) {
  Mem *m = (Mem *)calloc(1, sizeof(Mem));
  void *cv = CVodeCreate(CV_BDF, CV_NEWTON);
  N_Vector x = N_VNew_Serial(NX);
  N_Vector *xS = NULL;
  double t = 0.0;
  long nst = 0, nfe = 0;
  int flag = 0, j, k;
  struct sigaction caught, previous;
  if (catch_sigint) {
    interrupted = 0;
    memset(&caught, 0, sizeof(caught));
    caught.sa_handler = on_sigint;
    sigemptyset(&caught.sa_mask);
    sigaction(SIGINT, &caught, &previous);
  }
  if (!m || !cv || !x) {
    flag = -20; /* CV_MEM_FAIL */
    goto done;
  }
  m->p = p;
  m->Q = Q;
  m->stop = stop;
  memcpy(NV_DATA_S(x), x0, NX * sizeof(double));
  CVodeSetErrHandlerFn(cv, quiet, NULL);
  if ((flag = CVodeInit(cv, rhs, 0.0, x))) goto done;
  if ((flag = CVodeSStolerances(cv, rtol, atol))) goto done;
  if ((flag = CVodeSetUserData(cv, m))) goto done;
  if ((flag = CVodeSetMaxNumSteps(cv, max_steps))) goto done;
  {
    CVodeMem cm = (CVodeMem)cv;
    if (cm->cv_user_data != (void *)m || cm->cv_mxstep != max_steps || cm->cv_reltol != rtol ||
        cm->cv_lmm != CV_BDF) {
      flag = CV_ILL_INPUT; /* not the layout of the headers: writing into it would be unsafe */
      goto done;
    }
    cm->cv_linit = NULL;
    cm->cv_lsetup = lsetup;
    cm->cv_lsolve = lsolve;
    cm->cv_lfree = NULL;
    cm->cv_lmem = m;
    cm->cv_setupNonNull = TRUE;
  }
  if (ns > 0) {
    if (NB > 1) { /* the directions are in the state: CVODES's own have no Jacobian here */
      flag = CV_ILL_INPUT;
      goto done;
    }
    xS = N_VCloneVectorArray_Serial(ns, x);
    if (!xS) {
      flag = CV_MEM_FAIL;
      goto done;
    }
    for (j = 0; j < ns; ++j) memcpy(NV_DATA_S(xS[j]), S0 + j * NX, NX * sizeof(double));
    if ((flag = CVodeSensInit(cv, ns, CV_STAGGERED, sensitivity_rhs, xS))) goto done;
    if ((flag = CVodeSensEEtolerances(cv))) goto done;
    if ((flag = CVodeSetSensErrCon(cv, TRUE))) goto done;
  }
  for (k = 0; k < ngrid; ++k) {
    flag = CVode(cv, grid[k], x, &t, CV_NORMAL);
    if (flag < 0) goto done;
    flag = 0;
    memcpy(xout + k * NX, NV_DATA_S(x), NX * sizeof(double));
    if (ns > 0) {
      if ((flag = CVodeGetSens(cv, &t, xS))) goto done;
      for (j = 0; j < ns; ++j) memcpy(Sout + (k * ns + j) * NX, NV_DATA_S(xS[j]), NX * sizeof(double));
    }
  }
done:
  if (cv) {
    CVodeGetNumSteps(cv, &nst);
    CVodeGetNumRhsEvals(cv, &nfe);
    CVodeGetCurrentTime(cv, &t);
  }
  stats[0] = (double)nst;
  stats[1] = (double)nfe;
  stats[2] = m ? (double)m->njac : 0.0;
  stats[3] = m ? (double)m->njfull : 0.0;
  stats[4] = t;
  stats[5] = (catch_sigint && interrupted) || (stop && *stop) ? 1.0 : 0.0;
  if (catch_sigint) sigaction(SIGINT, &previous, NULL);
  if (xS) N_VDestroyVectorArray_Serial(xS, ns);
  if (x) N_VDestroy_Serial(x);
  if (cv) CVodeFree(&cv);
  free(m);
  return flag;
}
