/* Copyright (C) 2026 dolfinx_contact_s2s developers
 * SPDX-License-Identifier: MIT
 *
 * Compiled face kernels of dolfinx_contact_s2s (see face_c_backend.py), compiled with
 * _kernels.c into one module.
 *
 * A face is given by its K geometry nodes (K, 3) in the order of Basix's Lagrange
 * element on the face (polygon.FACE_ELEMENTS): K = 3 (P1 triangle), 4 (Q1
 * quadrilateral), 6 (P2 triangle), 9 (Q2 quadrilateral). Reference coordinates are
 * Basix's. The NumPy reference is kernels/polygon.py (evaluate, intersect); the results
 * agree to round-off, not to the bit (Basix tabulates in another order).
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

/* The face basis phi[k] and its derivatives dphi[d * K + k] at (x, y). Returns 0 for an
 * unsupported K. Basix's numbering: the square's vertices (0,0), (1,0), (0,1), (1,1),
 * its edges (0,1), (0,2), (1,3), (2,3); the triangle's edges (1,2), (0,2), (0,1). */
static int s2s_face_basis(int K, double x, double y, double *phi, double *dphi)
{
  if (K == 3)
  {
    phi[0] = 1.0 - x - y, phi[1] = x, phi[2] = y;
    dphi[0] = -1.0, dphi[1] = 1.0, dphi[2] = 0.0;
    dphi[3] = -1.0, dphi[4] = 0.0, dphi[5] = 1.0;
    return 1;
  }
  if (K == 4)
  {
    phi[0] = (1.0 - x) * (1.0 - y), phi[1] = x * (1.0 - y);
    phi[2] = (1.0 - x) * y, phi[3] = x * y;
    dphi[0] = -(1.0 - y), dphi[1] = 1.0 - y, dphi[2] = -y, dphi[3] = y;
    dphi[4] = -(1.0 - x), dphi[5] = -x, dphi[6] = 1.0 - x, dphi[7] = x;
    return 1;
  }
  if (K == 6)
  {
    const double l[3] = {1.0 - x - y, x, y};
    const double dl[2][3] = {{-1.0, 1.0, 0.0}, {-1.0, 0.0, 1.0}};
    const int edge[3][2] = {{1, 2}, {0, 2}, {0, 1}};
    for (int i = 0; i < 3; ++i)
    {
      phi[i] = l[i] * (2.0 * l[i] - 1.0);
      for (int d = 0; d < 2; ++d)
        dphi[d * 6 + i] = (4.0 * l[i] - 1.0) * dl[d][i];
    }
    for (int e = 0; e < 3; ++e)
    {
      const int a = edge[e][0], b = edge[e][1];
      phi[3 + e] = 4.0 * l[a] * l[b];
      for (int d = 0; d < 2; ++d)
        dphi[d * 6 + 3 + e] = 4.0 * (l[a] * dl[d][b] + l[b] * dl[d][a]);
    }
    return 1;
  }
  if (K == 9)
  {
    /* 1D quadratics at 0, 1, 1/2 and their derivatives, in x and in y. */
    const double u[3] = {(1.0 - x) * (1.0 - 2.0 * x), x * (2.0 * x - 1.0), 4.0 * x * (1.0 - x)};
    const double du[3] = {4.0 * x - 3.0, 4.0 * x - 1.0, 4.0 - 8.0 * x};
    const double v[3] = {(1.0 - y) * (1.0 - 2.0 * y), y * (2.0 * y - 1.0), 4.0 * y * (1.0 - y)};
    const double dv[3] = {4.0 * y - 3.0, 4.0 * y - 1.0, 4.0 - 8.0 * y};
    /* Node k sits at (ix[k], iy[k]) of the 1D nodes 0, 1, 1/2. */
    const int ix[9] = {0, 1, 0, 1, 2, 0, 1, 2, 2};
    const int iy[9] = {0, 0, 1, 1, 0, 2, 2, 1, 2};
    for (int k = 0; k < 9; ++k)
    {
      phi[k] = u[ix[k]] * v[iy[k]];
      dphi[k] = du[ix[k]] * v[iy[k]];
      dphi[9 + k] = u[ix[k]] * dv[iy[k]];
    }
    return 1;
  }
  return 0;
}

/* x (3) and the tangents dx[g * 2 + d] of the face with nodes c (K, 3) at (x, y). */
static void s2s_face_point(const double *c, int K, const double *xi, double *x, double *dx)
{
  double phi[9], dphi[18];
  s2s_face_basis(K, xi[0], xi[1], phi, dphi);
  for (int g = 0; g < 3; ++g)
  {
    double s = 0.0, s0 = 0.0, s1 = 0.0;
    for (int k = 0; k < K; ++k)
    {
      s += phi[k] * c[3 * k + g];
      s0 += dphi[k] * c[3 * k + g];
      s1 += dphi[K + k] * c[3 * k + g];
    }
    x[g] = s;
    if (dx)
    {
      dx[2 * g] = s0;
      dx[2 * g + 1] = s1;
    }
  }
}

void s2s_face_evaluate(const double *nodes, int K, const int32_t *rows, const double *xi, int P,
                       double *x, double *dx)
{
  for (int p = 0; p < P; ++p)
    s2s_face_point(nodes + (int64_t)rows[p] * K * 3, K, xi + 2 * p, x + 3 * p, dx + 6 * p);
}

/* A 3x3 matrix A (row-major) factored by Gaussian elimination with partial pivoting:
 * the pivot row and multipliers of each step and the upper triangle. ok = 0 if A is not
 * finite or singular relative to Hadamard's bound (round_off times the product of its
 * column lengths), as polygon._solve decides. */
typedef struct
{
  double U[9], f[3][3];
  int pivot[3], ok;
} s2s_lu3;

static void s2s_lu3_factor(const double *A_in, double round_off, s2s_lu3 *lu)
{
  double *A = lu->U, bound = 1.0, det = 1.0;
  lu->ok = 0;
  for (int i = 0; i < 9; ++i)
  {
    if (!isfinite(A_in[i]))
      return;
    A[i] = A_in[i];
  }
  for (int j = 0; j < 3; ++j)
    bound *= sqrt(A[j] * A[j] + A[3 + j] * A[3 + j] + A[6 + j] * A[6 + j]);
  for (int k = 0; k < 3; ++k)
  {
    int p = k;
    for (int i = k + 1; i < 3; ++i)
      if (fabs(A[3 * i + k]) > fabs(A[3 * p + k]))
        p = i;
    lu->pivot[k] = p;
    if (p != k)
    {
      for (int j = 0; j < 3; ++j)
      {
        const double s = A[3 * k + j];
        A[3 * k + j] = A[3 * p + j], A[3 * p + j] = s;
      }
      det = -det;
    }
    det *= A[3 * k + k];
    if (A[3 * k + k] == 0.0)
      return;
    for (int i = k + 1; i < 3; ++i)
    {
      const double f = A[3 * i + k] / A[3 * k + k];
      lu->f[i][k] = f;
      for (int j = k; j < 3; ++j)
        A[3 * i + j] -= f * A[3 * k + j];
    }
  }
  lu->ok = fabs(det) > round_off * bound;
}

/* Solve A z = b with the factors of A: the same operations on b as eliminating it with A.
 * Returns 0 if A was refused or b is not finite. */
static int s2s_lu3_solve(const s2s_lu3 *lu, const double *b_in, double *z)
{
  double b[3];
  for (int i = 0; i < 3; ++i)
  {
    if (!isfinite(b_in[i]))
      return 0;
    b[i] = b_in[i];
  }
  if (!lu->ok)
    return 0;
  for (int k = 0; k < 3; ++k)
  {
    const int p = lu->pivot[k];
    if (p != k)
    {
      const double s = b[k];
      b[k] = b[p], b[p] = s;
    }
    for (int i = k + 1; i < 3; ++i)
      b[i] -= lu->f[i][k] * b[k];
  }
  const double *U = lu->U;
  for (int i = 2; i >= 0; --i)
  {
    double s = b[i];
    for (int j = i + 1; j < 3; ++j)
      s -= U[3 * i + j] * z[j];
    z[i] = s / U[3 * i + i];
  }
  return 1;
}

/* A face ready for lines: its nodes relative to node 0, its size h (the largest node
 * distance from node 0) and the factors of the last start matrix, reused while the
 * next line gives the same matrix (the same direction: a flat contactor's normal). */
typedef struct
{
  const double *nodes;
  double c[27], h, key[9];
  int K, cached;
  s2s_lu3 start;
} s2s_face;

static void s2s_face_prepare(const double *nodes, int K, s2s_face *f)
{
  f->nodes = nodes, f->K = K, f->cached = 0, f->h = 0.0;
  for (int k = 0; k < K; ++k)
    for (int g = 0; g < 3; ++g)
      f->c[3 * k + g] = nodes[3 * k + g] - nodes[g];
  const double *c = f->c;
  for (int k = 0; k < K; ++k)
    f->h = fmax(f->h, sqrt(c[3 * k] * c[3 * k] + c[3 * k + 1] * c[3 * k + 1] +
                           c[3 * k + 2] * c[3 * k + 2]));
}

/* Where the line o + t d crosses face f: polygon.intersect for one line. The start is
 * the flat face through nodes 0, 1, 2 (final for K = 3), then Newton's method on
 * x(xi) - (o + t d) = 0 until a step is below tol (1 + |xi|) and tol (h + |t|). All
 * relative to node 0. Returns whether it converged. */
static int s2s_face_line_on(s2s_face *f, const double *origin, const double *d, int iterations,
                            double tol, double round_off, double *xi, double *t)
{
  const double *c = f->c;
  const int K = f->K;
  double o[3], A[9], z[3];
  for (int g = 0; g < 3; ++g)
  {
    o[g] = origin[g] - f->nodes[g];
    A[3 * g] = c[3 + g], A[3 * g + 1] = c[6 + g], A[3 * g + 2] = -d[g];
  }
  if (!f->cached || memcmp(f->key, A, sizeof A) != 0)
  {
    s2s_lu3_factor(A, round_off, &f->start);
    memcpy(f->key, A, sizeof A);
    f->cached = 1;
  }
  if (!s2s_lu3_solve(&f->start, o, z))
    return 0;
  xi[0] = z[0], xi[1] = z[1], *t = z[2];
  if (K == 3)
    return isfinite(xi[0]) && isfinite(xi[1]) && isfinite(*t);
  for (int it = 0; it < iterations; ++it)
  {
    double x[3], dx[6], r[3];
    s2s_lu3 lu;
    s2s_face_point(c, K, xi, x, dx);
    for (int g = 0; g < 3; ++g)
    {
      A[3 * g] = dx[2 * g], A[3 * g + 1] = dx[2 * g + 1], A[3 * g + 2] = -d[g];
      r[g] = x[g] - o[g] - *t * d[g];
    }
    s2s_lu3_factor(A, round_off, &lu);
    if (!s2s_lu3_solve(&lu, r, z))
      return 0;
    xi[0] -= z[0], xi[1] -= z[1], *t -= z[2];
    if (fabs(z[0]) <= tol * (1.0 + fabs(xi[0])) && fabs(z[1]) <= tol * (1.0 + fabs(xi[1])) &&
        fabs(z[2]) <= tol * (f->h + fabs(*t)))
      return isfinite(xi[0]) && isfinite(xi[1]) && isfinite(*t);
  }
  return 0;
}

void s2s_face_intersect(const double *nodes, int K, const int32_t *rows, const double *origins,
                        const double *directions, int P, int iterations, double tol,
                        double round_off, double *xi, double *t, int8_t *ok)
{
  s2s_face f;
  for (int p = 0; p < P; ++p)
  {
    if (p == 0 || rows[p] != rows[p - 1])
      s2s_face_prepare(nodes + (int64_t)rows[p] * K * 3, K, &f);
    ok[p] = (int8_t)s2s_face_line_on(&f, origins + 3 * p, directions + 3 * p, iterations, tol,
                                     round_off, xi + 2 * p, t + p);
    if (!ok[p])
      xi[2 * p] = xi[2 * p + 1] = t[p] = NAN;
  }
}

/* The monomials x^i y^j of Q_p at (x, y), m = j (p + 1) + i with (p + 1)^2 = M
 * (face_basis.FaceBasis.powers). */
static void s2s_monomials(int M, double x, double y, double *mono)
{
  const int p1 = M == 1 ? 1 : (M == 4 ? 2 : (M == 9 ? 3 : 4));
  const double px[4] = {1.0, x, x * x, x * x * x}, py[4] = {1.0, y, y * y, y * y * y};
  for (int j = 0; j < p1; ++j)
    for (int i = 0; i < p1; ++i)
      mono[j * p1 + i] = px[i] * py[j];
}

/* The N functions of a monomial table at the M monomials mono: out[n] = sum_m mono[m]
 * coef[m * N + n]; values below zero_below in magnitude are set to 0 (Basix's
 * round-off). */
static void s2s_monomial_values(const double *coef, int M, int N, const double *mono,
                                double zero_below, double *out)
{
  for (int n = 0; n < N; ++n)
  {
    double s = 0.0;
    for (int m = 0; m < M; ++m)
      s += mono[m] * coef[m * N + n];
    out[n] = fabs(s) < zero_below ? 0.0 : s;
  }
}

/* Friction's tangent at the unit normal n (face_backend.tangents): t = axis x n
 * normalized, then n x t for which = 2. */
static void s2s_tangent(const double *axis, const double *n, int which, double *t)
{
  t[0] = axis[1] * n[2] - axis[2] * n[1];
  t[1] = axis[2] * n[0] - axis[0] * n[2];
  t[2] = axis[0] * n[1] - axis[1] * n[0];
  const double length = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
  for (int d = 0; d < 3; ++d)
    t[d] /= length;
  if (which == 2)
  {
    const double a[3] = {t[0], t[1], t[2]};
    t[0] = n[1] * a[2] - n[2] * a[1];
    t[1] = n[2] * a[0] - n[0] * a[2];
    t[2] = n[0] * a[1] - n[1] * a[0];
  }
}

/* The local blocks of Eqs. (40)-(42) on faces, every step per point (face_backend.
 * face_coupling, the reference): the contact normal N = -n_C at the contactor point
 * xi, the target point met along it (Newton, Eq. 38; eta clipped to [0, 1]), the gap,
 * the bases (monomial tables: multiplier mu, contactor phi_c at xi, target phi_t at
 * eta) and the sums of s2s_segment_to_segment, with the coverage sum w mu (or mu^2).
 * Coordinates relative to the contactor face's node 0, as the reference shifts them.
 * Consecutive groups on the same pair of faces are summed into one block (face_backend.
 * runs gives their number and first groups). With which = 1 or 2, friction's tangent
 * (face_backend.tangents: T1 = axis x N / |axis x N|, T2 = N x T1) in place of N in the
 * blocks, and a zero gap. ok[s * Q + q] = 0 where Newton's method failed (the blocks
 * then hold NaN). */
void s2s_face_coupling(const double *c_nodes, int Kc, const double *c_orientation,
                       const double *t_nodes, int Kt, const int32_t *rows_c,
                       const int32_t *rows_t, const double *xi, const double *weights, int S,
                       int Q, const double *mu_coef, int Mm, int nk, const int32_t *mu_index,
                       const double *c_coef, int Mc, int nc, const int32_t *c_index,
                       const double *t_coef, int Mt, int nt, const int32_t *t_index,
                       int square, int iterations, double tol, double round_off,
                       double zero_below, const double *axis, int which, double *b_c,
                       double *b_t, double *g, double *coverage, int8_t *ok)
{
  int B = -1;
  for (int s = 0; s < S; ++s)
  {
    const int more = s > 0 && rows_c[s] == rows_c[s - 1] && rows_t[s] == rows_t[s - 1];
    B += !more;
    const double *c = c_nodes + (int64_t)rows_c[s] * Kc * 3;
    const double *t = t_nodes + (int64_t)rows_t[s] * Kt * 3;
    const double *mcoef = mu_coef + (int64_t)mu_index[s] * Mm * nk;
    const double *ccoef = c_coef + (int64_t)c_index[s] * Mc * nc;
    const double *tcoef = t_coef + (int64_t)t_index[s] * Mt * nt;
    double cl[27], tl[27];
    for (int k = 0; k < Kc; ++k)
      for (int d = 0; d < 3; ++d)
        cl[3 * k + d] = c[3 * k + d] + (-c[d]);
    for (int k = 0; k < Kt; ++k)
      for (int d = 0; d < 3; ++d)
        tl[3 * k + d] = t[3 * k + d] + (-c[d]);
    s2s_face target;
    s2s_face_prepare(tl, Kt, &target);
    double *bc = b_c + (int64_t)B * nk * nc * 3;
    double *bt = b_t + (int64_t)B * nk * nt * 3;
    double *gs = g + (int64_t)B * nk, *cv = coverage + (int64_t)B * nk;
    if (!more)
    {
      for (int i = 0; i < nk * nc * 3; ++i)
        bc[i] = 0.0;
      for (int i = 0; i < nk * nt * 3; ++i)
        bt[i] = 0.0;
      for (int k = 0; k < nk; ++k)
        gs[k] = cv[k] = 0.0;
    }
    double n[3];
    for (int q = 0; q < Q; ++q)
    {
      const int64_t sq = (int64_t)s * Q + q;
      const double *x = xi + 2 * sq;
      double xc[3], dx[6], xt[3], eta[2], tline, mu[16], pc[16], pt[16];
      if (q == 0 || Kc != 3) /* the tangents of a P1 face do not depend on xi */
      {
        s2s_face_point(c, Kc, x, xc, dx);
        n[0] = dx[2] * dx[5] - dx[4] * dx[3];
        n[1] = dx[4] * dx[1] - dx[0] * dx[5];
        n[2] = dx[0] * dx[3] - dx[2] * dx[1];
        const double length = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int d = 0; d < 3; ++d)
          n[d] = -(c_orientation[rows_c[s]] * (n[d] / length));
      }
      s2s_face_point(cl, Kc, x, xc, NULL);
      ok[sq] = (int8_t)s2s_face_line_on(&target, xc, n, iterations, tol, round_off, eta, &tline);
      if (!ok[sq])
        eta[0] = eta[1] = NAN;
      for (int d = 0; d < 2; ++d)
        eta[d] = eta[d] < 0.0 ? 0.0 : (eta[d] > 1.0 ? 1.0 : eta[d]);
      s2s_face_point(tl, Kt, eta, xt, NULL);
      double gap = (xc[0] - xt[0]) * n[0] + (xc[1] - xt[1]) * n[1] + (xc[2] - xt[2]) * n[2];
      double dir[3] = {n[0], n[1], n[2]};
      if (which > 0)
      {
        s2s_tangent(axis, n, which, dir);
        gap = 0.0;
      }
      double mono[16], mono_t[16];
      s2s_monomials(Mm, x[0], x[1], mono);
      s2s_monomial_values(mcoef, Mm, nk, mono, 0.0, mu);
      if (Mc != Mm)
        s2s_monomials(Mc, x[0], x[1], mono);
      s2s_monomial_values(ccoef, Mc, nc, mono, zero_below, pc);
      s2s_monomials(Mt, eta[0], eta[1], mono_t);
      s2s_monomial_values(tcoef, Mt, nt, mono_t, zero_below, pt);
      const double w = weights[sq];
      for (int k = 0; k < nk; ++k)
      {
        const double wm = mu[k] * w;
        gs[k] += wm * gap;
        cv[k] += (square ? mu[k] * mu[k] : mu[k]) * w;
        for (int j = 0; j < nc; ++j)
          for (int d = 0; d < 3; ++d)
            bc[(k * nc + j) * 3 + d] += wm * pc[j] * dir[d];
        for (int j = 0; j < nt; ++j)
          for (int d = 0; d < 3; ++d)
            bt[(k * nt + j) * 3 + d] -= wm * pt[j] * dir[d];
      }
    }
  }
}

/* Pull-back of one plane point x along the plane's normal n onto face c (segmentation.
 * _pull_back): xi, the outward unit normal (orientation sign) and the ratio of the
 * face's area element to the plane's. Returns whether the line met the face. */
static int s2s_face_pull_back_one(s2s_face *f, double sign, const double *x, const double *n,
                                  int iterations, double tol, double round_off, double *xi,
                                  double *normal, double *ratio)
{
  double t, y[3], dx[6], a[3];
  const int ok = s2s_face_line_on(f, x, n, iterations, tol, round_off, xi, &t);
  if (!ok)
    xi[0] = xi[1] = NAN;
  s2s_face_point(f->nodes, f->K, xi, y, dx);
  a[0] = dx[2] * dx[5] - dx[4] * dx[3];
  a[1] = dx[4] * dx[1] - dx[0] * dx[5];
  a[2] = dx[0] * dx[3] - dx[2] * dx[1];
  const double jac = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (normal)
    for (int d = 0; d < 3; ++d)
      normal[d] = sign * (a[d] / jac);
  *ratio = jac / fabs(a[0] * n[0] + a[1] * n[1] + a[2] * n[2]);
  return ok;
}

/* A triangle rule (X, W; Q points) on each piece (segmentation.PolygonSegmentation.
 * points): the plane point of each rule point, pulled back to the contactor face along
 * the plane's normal; its weight, the rule's times twice the triangle's area times the
 * ratio of area elements. */
void s2s_face_piece_points(const double *nodes, int K, const int32_t *rows,
                           const double *triangles, const double *origin, const double *frame,
                           int S, const double *X, const double *W, int Q, int iterations,
                           double tol, double round_off, double *xi, double *weights,
                           int8_t *ok)
{
  for (int s = 0; s < S; ++s)
  {
    const double *tr = triangles + 6 * s, *o = origin + 3 * s, *fr = frame + 9 * s;
    const double ab[2] = {tr[2] - tr[0], tr[3] - tr[1]}, ac[2] = {tr[4] - tr[0], tr[5] - tr[1]};
    const double det = fabs(ab[0] * ac[1] - ab[1] * ac[0]);
    s2s_face f;
    s2s_face_prepare(nodes + (int64_t)rows[s] * K * 3, K, &f);
    double ratio = 0.0, t;
    for (int q = 0; q < Q; ++q)
    {
      const int64_t sq = (int64_t)s * Q + q;
      double p[2], x[3];
      for (int d = 0; d < 2; ++d)
        p[d] = tr[d] + X[2 * q] * ab[d] + X[2 * q + 1] * ac[d];
      for (int g = 0; g < 3; ++g)
        x[g] = o[g] + (p[0] * fr[g] + p[1] * fr[3 + g]);
      if (q == 0 || K != 3) /* the area ratio of a P1 face does not depend on xi */
        ok[sq] = (int8_t)s2s_face_pull_back_one(&f, 1.0, x, fr + 6, iterations, tol,
                                                round_off, xi + 2 * sq, NULL, &ratio);
      else if (!(ok[sq] = (int8_t)s2s_face_line_on(&f, x, fr + 6, iterations, tol, round_off,
                                                    xi + 2 * sq, &t)))
        xi[2 * sq] = xi[2 * sq + 1] = NAN;
      weights[sq] = det * W[q] * ratio;
    }
  }
}

/* The m corners of a face of K nodes, counter-clockwise in the reference cell
 * (polygon.corner_nodes: Basix numbers the square's vertices (0,0), (1,0), (0,1), (1,1)). */
static int s2s_corners(const double *nodes, int K, double *out)
{
  static const int order[2][4] = {{0, 1, 2, 0}, {0, 1, 3, 2}};
  const int m = (K == 3 || K == 6) ? 3 : 4;
  for (int i = 0; i < m; ++i)
    for (int g = 0; g < 3; ++g)
      out[3 * i + g] = nodes[3 * order[m - 3][i] + g];
  return m;
}

/* The unit vector area of corners (relative to their mean) times sign, and whether the
 * area exceeds round_off times the size squared (polygon.project_faces' outward and
 * _check_areas). */
static int s2s_outward(const double *corners, int m, double sign, double round_off, double *n)
{
  double mean[3], rel[12], v[3] = {0.0, 0.0, 0.0}, size = 0.0;
  for (int g = 0; g < 3; ++g)
  {
    double s = 0.0;
    for (int i = 0; i < m; ++i)
      s += corners[3 * i + g];
    mean[g] = s / m;
  }
  for (int i = 0; i < m; ++i)
    for (int g = 0; g < 3; ++g)
      rel[3 * i + g] = corners[3 * i + g] - mean[g];
  for (int i = 0; i < m; ++i)
  {
    const double *a = rel + 3 * i, *b = rel + 3 * ((i + 1) % m);
    v[0] += a[1] * b[2] - a[2] * b[1];
    v[1] += a[2] * b[0] - a[0] * b[2];
    v[2] += a[0] * b[1] - a[1] * b[0];
    size = fmax(size, sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]));
  }
  const double length = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int g = 0; g < 3; ++g)
    n[g] = sign * (v[g] / length);
  return 0.5 * length > round_off * size * size;
}

/* Corners relative to origin drawn in the plane (e1, e2), counter-clockwise. */
static void s2s_plane_polygon(const double *corners, int m, const double *origin,
                              const double *frame, double *poly)
{
  double area = 0.0;
  for (int i = 0; i < m; ++i)
  {
    double r[3];
    for (int g = 0; g < 3; ++g)
      r[g] = corners[3 * i + g] - origin[g];
    for (int d = 0; d < 2; ++d)
      poly[2 * i + d] = r[0] * frame[3 * d] + r[1] * frame[3 * d + 1] + r[2] * frame[3 * d + 2];
  }
  for (int i = 0; i < m; ++i)
  {
    const int j = (i + 1) % m;
    area += poly[2 * i] * poly[2 * j + 1] - poly[2 * j] * poly[2 * i + 1];
  }
  if (area < 0.0)
    for (int i = 0; i < m / 2; ++i)
      for (int d = 0; d < 2; ++d)
      {
        const double s = poly[2 * i + d];
        poly[2 * i + d] = poly[2 * (m - 1 - i) + d], poly[2 * (m - 1 - i) + d] = s;
      }
}

/* polygon.project_faces for candidate pairs (ic, it): the contactor face's plane (origin
 * at its corners' centroid, frame rows e1, e2, n), both corner polygons in it, whether
 * the outward normals oppose, and whether each face has an area (ok_c, ok_t). A face's
 * own quantities are computed once while the candidates repeat it. */
void s2s_face_project(const double *c_nodes, int Kc, const double *c_orientation,
                      const double *t_nodes, int Kt, const double *t_orientation,
                      const int32_t *ic, const int32_t *it, int N, double round_off,
                      double *origin, double *frame, double *c_poly, double *t_poly,
                      int8_t *facing, int8_t *ok_c, int8_t *ok_t)
{
  double cc[12], tc[12], o[3], f[9], nt[3], poly[8];
  int mc = 0, mt = 0, area_c = 0, area_t = 0;
  for (int p = 0; p < N; ++p)
  {
    if (p == 0 || ic[p] != ic[p - 1])
    {
      double rel[12], edge[3];
      mc = s2s_corners(c_nodes + (int64_t)ic[p] * Kc * 3, Kc, cc);
      area_c = s2s_outward(cc, mc, 1.0, round_off, f + 6);
      for (int g = 0; g < 3; ++g)
      {
        double s = 0.0;
        for (int i = 0; i < mc; ++i)
          s += cc[3 * i + g];
        o[g] = s / mc;
      }
      for (int i = 0; i < mc; ++i)
        for (int g = 0; g < 3; ++g)
          rel[3 * i + g] = cc[3 * i + g] - o[g];
      s2s_outward(rel, mc, c_orientation[ic[p]], round_off, f + 6);
      const double *n = f + 6;
      for (int g = 0; g < 3; ++g)
        edge[g] = rel[3 + g] - rel[g];
      const double en = edge[0] * n[0] + edge[1] * n[1] + edge[2] * n[2];
      for (int g = 0; g < 3; ++g)
        f[g] = edge[g] - en * n[g];
      const double l = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      for (int g = 0; g < 3; ++g)
        f[g] /= l;
      f[3] = n[1] * f[2] - n[2] * f[1];
      f[4] = n[2] * f[0] - n[0] * f[2];
      f[5] = n[0] * f[1] - n[1] * f[0];
      s2s_plane_polygon(cc, mc, o, f, poly);
    }
    if (p == 0 || it[p] != it[p - 1])
    {
      mt = s2s_corners(t_nodes + (int64_t)it[p] * Kt * 3, Kt, tc);
      area_t = s2s_outward(tc, mt, t_orientation[it[p]], round_off, nt);
    }
    for (int i = 0; i < 3; ++i)
      origin[3 * p + i] = o[i];
    for (int i = 0; i < 9; ++i)
      frame[9 * p + i] = f[i];
    for (int i = 0; i < 2 * mc; ++i)
      c_poly[2 * mc * p + i] = poly[i];
    s2s_plane_polygon(tc, mt, o, f, t_poly + 2 * mt * p);
    facing[p] = f[6] * nt[0] + f[7] * nt[1] + f[8] * nt[2] < 0.0;
    ok_c[p] = (int8_t)area_c, ok_t[p] = (int8_t)area_t;
  }
}

/* The gap at each piece's centroid (segmentation.PolygonSegmentation.cut): the centroid
 * of the plane triangle pulled back to the contactor face along the plane's normal, then
 * the line along the contactor's outward normal there met with the target face: its
 * parameter, (x_T - x_C) . n_C. A face is prepared once while the pieces repeat it. */
void s2s_face_piece_gaps(const double *c_nodes, int Kc, const double *c_orientation,
                         const double *t_nodes, int Kt, const int32_t *rows_c,
                         const int32_t *rows_t, const double *triangles, const double *origin,
                         const double *frame, int S, int iterations, double tol,
                         double round_off, double *gap, int8_t *ok_c, int8_t *ok_t)
{
  s2s_face contactor, target;
  for (int s = 0; s < S; ++s)
  {
    const double *tr = triangles + 6 * s, *o = origin + 3 * s, *fr = frame + 9 * s;
    double m[2], x[3], xi[2], xc[3], normal[3], ratio, eta[2];
    if (s == 0 || rows_c[s] != rows_c[s - 1])
      s2s_face_prepare(c_nodes + (int64_t)rows_c[s] * Kc * 3, Kc, &contactor);
    if (s == 0 || rows_t[s] != rows_t[s - 1])
      s2s_face_prepare(t_nodes + (int64_t)rows_t[s] * Kt * 3, Kt, &target);
    for (int d = 0; d < 2; ++d)
      m[d] = (tr[d] + tr[2 + d] + tr[4 + d]) / 3.0;
    for (int g = 0; g < 3; ++g)
      x[g] = o[g] + (m[0] * fr[g] + m[1] * fr[3 + g]);
    ok_c[s] = (int8_t)s2s_face_pull_back_one(&contactor, c_orientation[rows_c[s]], x, fr + 6,
                                             iterations, tol, round_off, xi, normal, &ratio);
    s2s_face_point(contactor.nodes, Kc, xi, xc, NULL);
    ok_t[s] = (int8_t)s2s_face_line_on(&target, xc, normal, iterations, tol, round_off, eta,
                                       gap + s);
    if (!ok_t[s])
      gap[s] = NAN;
  }
}
