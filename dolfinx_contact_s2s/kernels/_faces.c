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

/* Solve A z = b (3x3, row-major) by Gaussian elimination with partial pivoting. Returns 0
 * if A is not finite or singular relative to Hadamard's bound (round_off times the
 * product of its column lengths), as polygon._solve decides. */
static int s2s_solve3(const double *A_in, const double *b_in, double round_off, double *z)
{
  double A[9], b[3], bound = 1.0;
  for (int i = 0; i < 9; ++i)
  {
    if (!isfinite(A_in[i]))
      return 0;
    A[i] = A_in[i];
  }
  for (int i = 0; i < 3; ++i)
  {
    if (!isfinite(b_in[i]))
      return 0;
    b[i] = b_in[i];
  }
  for (int j = 0; j < 3; ++j)
    bound *= sqrt(A[j] * A[j] + A[3 + j] * A[3 + j] + A[6 + j] * A[6 + j]);
  double det = 1.0;
  for (int k = 0; k < 3; ++k)
  {
    int p = k;
    for (int i = k + 1; i < 3; ++i)
      if (fabs(A[3 * i + k]) > fabs(A[3 * p + k]))
        p = i;
    if (p != k)
    {
      for (int j = 0; j < 3; ++j)
      {
        const double s = A[3 * k + j];
        A[3 * k + j] = A[3 * p + j], A[3 * p + j] = s;
      }
      const double s = b[k];
      b[k] = b[p], b[p] = s;
      det = -det;
    }
    det *= A[3 * k + k];
    if (A[3 * k + k] == 0.0)
      return 0;
    for (int i = k + 1; i < 3; ++i)
    {
      const double f = A[3 * i + k] / A[3 * k + k];
      for (int j = k; j < 3; ++j)
        A[3 * i + j] -= f * A[3 * k + j];
      b[i] -= f * b[k];
    }
  }
  if (!(fabs(det) > round_off * bound))
    return 0;
  for (int i = 2; i >= 0; --i)
  {
    double s = b[i];
    for (int j = i + 1; j < 3; ++j)
      s -= A[3 * i + j] * z[j];
    z[i] = s / A[3 * i + i];
  }
  return 1;
}

/* Where the line o + t d crosses face c (K nodes): polygon.intersect for one line. The
 * start is the flat face through nodes 0, 1, 2 (final for K = 3), then Newton's method
 * on x(xi) - (o + t d) = 0 until a step is below tol (1 + |xi|) and tol (h + |t|). All
 * relative to node 0. Returns whether it converged. */
static int s2s_face_line(const double *nodes, int K, const double *origin, const double *d,
                         int iterations, double tol, double round_off, double *xi, double *t)
{
  double c[27], o[3], A[9], z[3];
  for (int k = 0; k < K; ++k)
    for (int g = 0; g < 3; ++g)
      c[3 * k + g] = nodes[3 * k + g] - nodes[g];
  for (int g = 0; g < 3; ++g)
  {
    o[g] = origin[g] - nodes[g];
    A[3 * g] = c[3 + g], A[3 * g + 1] = c[6 + g], A[3 * g + 2] = -d[g];
  }
  if (!s2s_solve3(A, o, round_off, z))
    return 0;
  xi[0] = z[0], xi[1] = z[1], *t = z[2];
  if (K == 3)
    return isfinite(xi[0]) && isfinite(xi[1]) && isfinite(*t);
  double h = 0.0;
  for (int k = 0; k < K; ++k)
    h = fmax(h, sqrt(c[3 * k] * c[3 * k] + c[3 * k + 1] * c[3 * k + 1] +
                     c[3 * k + 2] * c[3 * k + 2]));
  for (int it = 0; it < iterations; ++it)
  {
    double x[3], dx[6], r[3];
    s2s_face_point(c, K, xi, x, dx);
    for (int g = 0; g < 3; ++g)
    {
      A[3 * g] = dx[2 * g], A[3 * g + 1] = dx[2 * g + 1], A[3 * g + 2] = -d[g];
      r[g] = x[g] - o[g] - *t * d[g];
    }
    if (!s2s_solve3(A, r, round_off, z))
      return 0;
    xi[0] -= z[0], xi[1] -= z[1], *t -= z[2];
    if (fabs(z[0]) <= tol * (1.0 + fabs(xi[0])) && fabs(z[1]) <= tol * (1.0 + fabs(xi[1])) &&
        fabs(z[2]) <= tol * (h + fabs(*t)))
      return isfinite(xi[0]) && isfinite(xi[1]) && isfinite(*t);
  }
  return 0;
}

void s2s_face_intersect(const double *nodes, int K, const int32_t *rows, const double *origins,
                        const double *directions, int P, int iterations, double tol,
                        double round_off, double *xi, double *t, int8_t *ok)
{
  for (int p = 0; p < P; ++p)
  {
    ok[p] = (int8_t)s2s_face_line(nodes + (int64_t)rows[p] * K * 3, K, origins + 3 * p,
                                  directions + 3 * p, iterations, tol, round_off, xi + 2 * p,
                                  t + p);
    if (!ok[p])
      xi[2 * p] = xi[2 * p + 1] = t[p] = NAN;
  }
}
