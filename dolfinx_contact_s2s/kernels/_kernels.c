/* Copyright (C) 2026 dolfinx_contact_s2s developers
 * SPDX-License-Identifier: MIT
 *
 * Compiled contact kernels of dolfinx_contact_s2s (see c_backend.py).
 *
 * Facets are 2D curves x(xi) = sum_m c[m] xi^m with coefficients c of shape (M, 2),
 * M = p + 1 for a degree-p coordinate map (numpy_backend.facet_coefficients). All
 * arrays are C-contiguous; rows select one facet per point. No defaults live here:
 * tolerances and iteration counts come from the Python layer.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

/* x, x' and x'' of facet c (M coefficients, gdim 2) at xi, by Horner's rule. */
static void s2s_point(const double *c, int M, double xi, double *x, double *dx, double *ddx)
{
  double x0 = c[2 * (M - 1)], x1 = c[2 * (M - 1) + 1];
  for (int m = M - 2; m >= 0; --m)
  {
    x0 = x0 * xi + c[2 * m];
    x1 = x1 * xi + c[2 * m + 1];
  }
  x[0] = x0;
  x[1] = x1;
  if (!dx)
    return;
  if (M < 2)
  {
    dx[0] = dx[1] = 0.0;
  }
  else
  {
    double d0 = c[2 * (M - 1)] * (M - 1), d1 = c[2 * (M - 1) + 1] * (M - 1);
    for (int m = M - 2; m >= 1; --m)
    {
      d0 = d0 * xi + c[2 * m] * m;
      d1 = d1 * xi + c[2 * m + 1] * m;
    }
    dx[0] = d0;
    dx[1] = d1;
  }
  if (!ddx)
    return;
  if (M < 3)
  {
    ddx[0] = ddx[1] = 0.0;
  }
  else
  {
    double e0 = c[2 * (M - 1)] * (M - 1) * (M - 2), e1 = c[2 * (M - 1) + 1] * (M - 1) * (M - 2);
    for (int m = M - 2; m >= 2; --m)
    {
      e0 = e0 * xi + c[2 * m] * m * (m - 1);
      e1 = e1 * xi + c[2 * m + 1] * m * (m - 1);
    }
    ddx[0] = e0;
    ddx[1] = e1;
  }
}

/* x(xi) - c[0] of facet c, without forming x(xi): relative to the facet's first point,
 * so that a facet far from the origin keeps the digits of its own size. */
static void s2s_offset(const double *c, int M, double xi, double *r)
{
  double r0 = 0.0, r1 = 0.0;
  for (int m = M - 1; m >= 1; --m)
  {
    r0 = (r0 + c[2 * m]) * xi;
    r1 = (r1 + c[2 * m + 1]) * xi;
  }
  r[0] = r0;
  r[1] = r1;
}

/* Whether facet c is straight: every coefficient beyond the linear one is exactly 0. */
static int s2s_straight(const double *c, int M)
{
  for (int m = 2; m < M; ++m)
    if (c[2 * m] != 0.0 || c[2 * m + 1] != 0.0)
      return 0;
  return 1;
}

void s2s_facet_coefficients(const double *basis, int M, int K, const int32_t *local_facet,
                            int F, const double *coords, int gdim, double *out)
{
  for (int f = 0; f < F; ++f)
  {
    const double *b = basis + (int64_t)local_facet[f] * M * K;
    const double *x = coords + (int64_t)f * K * gdim;
    double *o = out + (int64_t)f * M * gdim;
    for (int m = 0; m < M; ++m)
      for (int g = 0; g < gdim; ++g)
      {
        double s = 0.0;
        for (int k = 0; k < K; ++k)
          s += b[m * K + k] * x[k * gdim + g];
        o[m * gdim + g] = s;
      }
  }
}

void s2s_evaluate(const double *c, int M, const int32_t *rows, const double *xi, int P,
                  double *x, double *dx, double *ddx)
{
  for (int p = 0; p < P; ++p)
    s2s_point(c + (int64_t)rows[p] * M * 2, M, xi[p], x + 2 * p, dx ? dx + 2 * p : 0,
              ddx ? ddx + 2 * p : 0);
}

/* Values at s of the K functions of table t (M monomial coefficients each), Horner. */
static void s2s_table_values(const double *t, int M, int K, double s, double *out)
{
  for (int k = 0; k < K; ++k)
  {
    double v = t[(M - 1) * K + k];
    for (int m = M - 2; m >= 0; --m)
      v = v * s + t[m * K + k];
    out[k] = v;
  }
}

void s2s_facet_basis(const double *table, int M, int K, const int32_t *local_facet,
                     const double *xi, int P, double *out)
{
  for (int p = 0; p < P; ++p)
    s2s_table_values(table + (int64_t)local_facet[p] * M * K, M, K, xi[p], out + (int64_t)p * K);
}

void s2s_cell_normals(const double *tables, const double *coords, int P, int K,
                      const double *reference_normals, double *out)
{
  /* J[g][d] = sum_k x[k][g] dphi_k/dX_d; n = J^{-T} n_ref, normalised (gdim = tdim = 2). */
  for (int p = 0; p < P; ++p)
  {
    double J[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
    const double *x = coords + (int64_t)p * K * 2;
    for (int d = 0; d < 2; ++d)
    {
      const double *t = tables + ((int64_t)d * P + p) * K;
      for (int k = 0; k < K; ++k)
      {
        J[0][d] += x[2 * k] * t[k];
        J[1][d] += x[2 * k + 1] * t[k];
      }
    }
    /* Solve J^T n = n_ref. */
    double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    const double *r = reference_normals + 2 * p;
    double n0 = (J[1][1] * r[0] - J[1][0] * r[1]) / det;
    double n1 = (-J[0][1] * r[0] + J[0][0] * r[1]) / det;
    double len = sqrt(n0 * n0 + n1 * n1);
    out[2 * p] = n0 / len;
    out[2 * p + 1] = n1 / len;
  }
}

static void s2s_normal(const double *c, int M, double orientation, double xi, double *n)
{
  double x[2], dx[2];
  s2s_point(c, M, xi, x, dx, 0);
  double n0 = dx[1] * orientation, n1 = -dx[0] * orientation;
  double len = sqrt(n0 * n0 + n1 * n1);
  n[0] = n0 / len;
  n[1] = n1 / len;
}

void s2s_outward_normals(const double *c, int M, const double *orientation, const int32_t *rows,
                         const double *xi, int P, double *out)
{
  for (int p = 0; p < P; ++p)
    s2s_normal(c + (int64_t)rows[p] * M * 2, M, orientation[rows[p]], xi[p], out + 2 * p);
}

/* Closest point on facet c of the point c[0] + (y0, y1), given relative to the facet's
 * first point: closed form if straight, else Newton from 1/2. */
static double s2s_project_local(const double *c, int M, double y0, double y1, int iterations,
                                double tol)
{
  if (s2s_straight(c, M))
  {
    double t0 = M > 1 ? c[2] : 0.0, t1 = M > 1 ? c[3] : 0.0;
    return (y0 * t0 + y1 * t1) / (t0 * t0 + t1 * t1);
  }
  double xi = 0.5, x[2], dx[2], ddx[2], r[2];
  for (int it = 0; it < iterations; ++it)
  {
    s2s_point(c, M, xi, x, dx, ddx);
    s2s_offset(c, M, xi, r);
    double r0 = r[0] - y0, r1 = r[1] - y1;
    double f = r0 * dx[0] + r1 * dx[1];
    double df = (dx[0] * dx[0] + dx[1] * dx[1]) + (r0 * ddx[0] + r1 * ddx[1]);
    double step = f / df;
    xi -= step;
    if (fabs(step) <= tol * (1.0 + fabs(xi)))
      break;
  }
  return xi;
}

/* Closest point of y on facet c, relative to the facet's first point. */
static double s2s_project_one(const double *c, int M, const double *y, int iterations,
                              double tol)
{
  return s2s_project_local(c, M, y[0] - c[0], y[1] - c[1], iterations, tol);
}

void s2s_project(const double *c, int M, const int32_t *rows, const double *points, int P,
                 int iterations, double tol, double *xi)
{
  for (int p = 0; p < P; ++p)
    xi[p] = s2s_project_one(c + (int64_t)rows[p] * M * 2, M, points + 2 * p, iterations, tol);
}

/* Parameter where the line o + t d crosses facet cf: closed form if straight, else Newton
 * from 1/2 relative to the facet's first point. */
static double s2s_intersect_one(const double *cf, int M, const double *o, const double *d,
                                int iterations, double tol)
{
  double q0 = -d[1], q1 = d[0];
  if (s2s_straight(cf, M))
  {
    double t0 = M > 1 ? cf[2] : 0.0, t1 = M > 1 ? cf[3] : 0.0;
    return -((cf[0] - o[0]) * q0 + (cf[1] - o[1]) * q1) / (t0 * q0 + t1 * q1);
  }
  double o0 = o[0] - cf[0], o1 = o[1] - cf[1];
  double e = 0.5, x[2], dx[2], r[2];
  for (int it = 0; it < iterations; ++it)
  {
    s2s_point(cf, M, e, x, dx, 0);
    s2s_offset(cf, M, e, r);
    double f = (r[0] - o0) * q0 + (r[1] - o1) * q1;
    double df = dx[0] * q0 + dx[1] * q1;
    double step = f / df;
    e -= step;
    if (fabs(step) <= tol * (1.0 + fabs(e)))
      break;
  }
  return e;
}

void s2s_intersect(const double *c, int M, const int32_t *rows, const double *origins,
                   const double *directions, int P, int iterations, double tol, double *eta)
{
  for (int p = 0; p < P; ++p)
    eta[p] = s2s_intersect_one(c + (int64_t)rows[p] * M * 2, M, origins + 2 * p,
                               directions + 2 * p, iterations, tol);
}

void s2s_segment_to_segment(const double *mu, const double *phi_c, const double *phi_t,
                            const double *normals, const double *weights, const double *gaps,
                            int S, int Q, int nk, int nc, int nt, int gdim, double *b_c,
                            double *b_t, double *g)
{
  for (int s = 0; s < S; ++s)
  {
    double *bc = b_c + (int64_t)s * nk * nc * gdim;
    double *bt = b_t + (int64_t)s * nk * nt * gdim;
    double *gs = g + (int64_t)s * nk;
    for (int i = 0; i < nk * nc * gdim; ++i)
      bc[i] = 0.0;
    for (int i = 0; i < nk * nt * gdim; ++i)
      bt[i] = 0.0;
    for (int k = 0; k < nk; ++k)
      gs[k] = 0.0;
    for (int q = 0; q < Q; ++q)
    {
      int64_t sq = (int64_t)s * Q + q;
      const double w = weights[sq];
      const double *m = mu + sq * nk;
      const double *pc = phi_c + sq * nc;
      const double *pt = phi_t + sq * nt;
      const double *n = normals + sq * gdim;
      for (int k = 0; k < nk; ++k)
      {
        double wm = m[k] * w;
        gs[k] += wm * gaps[sq];
        for (int j = 0; j < nc; ++j)
          for (int d = 0; d < gdim; ++d)
            bc[(k * nc + j) * gdim + d] += wm * pc[j] * n[d];
        for (int j = 0; j < nt; ++j)
          for (int d = 0; d < gdim; ++d)
            bt[(k * nt + j) * gdim + d] -= wm * pt[j] * n[d];
      }
    }
  }
}

/* The local blocks of Eqs. (40)-(42) of S groups of Q points on edges, in one pass:
 * what pair._integrate composes from outward_normals, intersect, evaluate, the bases and
 * segment_to_segment, with the same operations. Group s pairs contactor facet gc[s] with
 * target facet gt[s]; points and gaps are taken relative to the contactor facet's first
 * point. The multiplier is mu_table (Mm coefficients of nk functions) at xi, or 1 - xi
 * where flip[gc]; the displacement bases are the tables of each local facet (lf_c, lf_t),
 * of the facet's own nc and nt functions. tangent: T = (N_1, -N_0) and no gap. Outputs:
 * b_c (S, nk, nc * 2), b_t (S, nk, nt * 2), g, sig and cov (S, nk): sum w mu g,
 * sum w mu, sum w mu^2 (mu if !square). */
void s2s_edge_coupling(const double *cc, int Mc, const double *c_orientation, const double *tc,
                       int Mt, const int32_t *gc, const int32_t *gt, int S, int Q,
                       const double *xi, const double *weights, const double *mu_table, int Mm,
                       int nk, const int8_t *flip, const double *c_table, int Mp, int nc,
                       const int32_t *lf_c, const double *t_table, int Mq, int nt,
                       const int32_t *lf_t, int tangent, int square, int iterations, double tol,
                       double *b_c, double *b_t, double *g, double *sig, double *cov)
{
  double cl[2 * 8], tl[2 * 8], mu[16], pc[16], pt[16];
  for (int s = 0; s < S; ++s)
  {
    const double *c = cc + (int64_t)gc[s] * Mc * 2, *t = tc + (int64_t)gt[s] * Mt * 2;
    for (int i = 0; i < 2 * Mc; ++i)
      cl[i] = i < 2 ? c[i] + -c[i] : c[i];
    for (int i = 0; i < 2 * Mt; ++i)
      tl[i] = i < 2 ? t[i] + -c[i] : t[i];
    double *bc = b_c + (int64_t)s * nk * nc * 2, *bt = b_t + (int64_t)s * nk * nt * 2;
    double *gs = g + (int64_t)s * nk, *ss = sig + (int64_t)s * nk, *vs = cov + (int64_t)s * nk;
    for (int i = 0; i < nk * nc * 2; ++i)
      bc[i] = 0.0;
    for (int i = 0; i < nk * nt * 2; ++i)
      bt[i] = 0.0;
    for (int k = 0; k < nk; ++k)
      gs[k] = ss[k] = vs[k] = 0.0;
    /* A straight facet's normal is the same at every point (x' = c[1] to the bit). */
    int straight = s2s_straight(c, Mc);
    double n[2];
    for (int q = 0; q < Q; ++q)
    {
      int64_t sq = (int64_t)s * Q + q;
      double x = xi[sq], w = weights[sq], xc[2], xt[2];
      if (q == 0 || !straight)
      {
        s2s_normal(c, Mc, c_orientation[gc[s]], x, n);
        n[0] = -n[0];
        n[1] = -n[1];
      }
      s2s_point(cl, Mc, x, xc, 0, 0);
      double eta = s2s_intersect_one(tl, Mt, xc, n, iterations, tol);
      eta = eta < 0.0 ? 0.0 : (eta > 1.0 ? 1.0 : eta);
      s2s_point(tl, Mt, eta, xt, 0, 0);
      double gap = (xc[0] - xt[0]) * n[0] + (xc[1] - xt[1]) * n[1];
      double dir[2] = {n[0], n[1]};
      if (tangent)
      {
        dir[0] = n[1];
        dir[1] = -n[0];
        gap = 0.0 * gap;
      }
      s2s_table_values(mu_table, Mm, nk, flip[gc[s]] ? 1.0 - x : x, mu);
      s2s_table_values(c_table + (int64_t)lf_c[gc[s]] * Mp * nc, Mp, nc, x, pc);
      s2s_table_values(t_table + (int64_t)lf_t[gt[s]] * Mq * nt, Mq, nt, eta, pt);
      for (int k = 0; k < nk; ++k)
      {
        double wm = mu[k] * w;
        gs[k] += wm * gap;
        ss[k] += mu[k] * w;
        vs[k] += (square ? mu[k] * mu[k] : mu[k]) * w;
        for (int j = 0; j < nc; ++j)
          for (int d = 0; d < 2; ++d)
            bc[(k * nc + j) * 2 + d] += wm * pc[j] * dir[d];
        for (int j = 0; j < nt; ++j)
          for (int d = 0; d < 2; ++d)
            bt[(k * nt + j) * 2 + d] -= wm * pt[j] * dir[d];
      }
    }
  }
}

void s2s_clip_segments(const double *cc, int Mc, const double *c_orientation, const double *tc,
                       int Mt, const double *t_orientation, const int32_t *ic, const int32_t *it,
                       int N, double radius, double min_length, double round_off,
                       int iterations, double tol, double *lo, double *hi, int8_t *keep)
{
  for (int p = 0; p < N; ++p)
  {
    const double *c = cc + (int64_t)ic[p] * Mc * 2;
    const double *t = tc + (int64_t)it[p] * Mt * 2;
    double n_c[2], n_t[2];
    s2s_normal(c, Mc, c_orientation[ic[p]], 0.5, n_c);
    s2s_normal(t, Mt, t_orientation[it[p]], 0.5, n_t);
    lo[p] = hi[p] = 0.0;
    keep[p] = 0;
    if (!(n_c[0] * n_t[0] + n_c[1] * n_t[1] < 0.0))
      continue;
    /* Everything relative to the contactor's first point (the facets' own digits). */
    double s0 = t[0] - c[0], s1 = t[1] - c[1], rb[2], rm[2], rt[2];
    s2s_offset(t, Mt, 1.0, rb);
    double a = s2s_project_local(c, Mc, s0, s1, iterations, tol);
    double b = s2s_project_local(c, Mc, s0 + rb[0], s1 + rb[1], iterations, tol);
    double l = fmin(a, b), h = fmax(a, b);
    l = fmin(fmax(l, 0.0), 1.0);
    h = fmin(fmax(h, 0.0), 1.0);
    lo[p] = l;
    hi[p] = h;
    s2s_offset(c, Mc, 0.5 * (l + h), rm);
    s2s_offset(t, Mt, 0.5, rt);
    double d = (s0 + rt[0] - rm[0]) * n_c[0] + (s1 + rt[1] - rm[1]) * n_c[1];
    /* Pieces no longer than the round-off of the projections are slivers. */
    double c1[2];
    s2s_point(c, Mc, 1.0, c1, 0, 0);
    double chord = hypot(c1[0] - c[0], c1[1] - c[1]);
    double scale = fmax(fmax(fabs(c[0]), fabs(c[1])), fmax(fabs(c1[0]), fabs(c1[1])));
    double shortest = fmax(min_length, round_off * (scale + chord) / chord);
    keep[p] = (h - l > shortest) && (fabs(d) <= radius);
  }
}

void s2s_bounding_boxes(const double *c, int M, int F, int samples, double pad, double *out)
{
  for (int f = 0; f < F; ++f)
  {
    const double *cf = c + (int64_t)f * M * 2;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, x[2];
    for (int i = 0; i < samples; ++i)
    {
      double xi = (samples > 1) ? ((i == samples - 1) ? 1.0 : i * (1.0 / (samples - 1))) : 0.0;
      s2s_point(cf, M, xi, x, 0, 0);
      for (int g = 0; g < 2; ++g)
      {
        lo[g] = fmin(lo[g], x[g]);
        hi[g] = fmax(hi[g], x[g]);
      }
    }
    /* Samples bound a straight facet exactly; a curved one may bulge between them. */
    double d0 = hi[0] - lo[0], d1 = hi[1] - lo[1];
    double p = s2s_straight(cf, M) ? 0.0 : pad * sqrt(d0 * d0 + d1 * d1);
    double *o = out + (int64_t)f * 4;
    o[0] = lo[0] - p;
    o[1] = lo[1] - p;
    o[2] = hi[0] + p;
    o[3] = hi[1] + p;
  }
}

/* Sum duplicate (row, col) entries into CSR with sorted columns; returns the number of
 * nonzeros, or -1 if a row is out of range (0 <= row < nrows). Duplicates are summed in
 * the order of the entries. */
int64_t s2s_coo_to_csr(int64_t nrows, int64_t n, const int64_t *rows, const int64_t *cols,
                       const double *values, int64_t *indptr, int64_t *indices, double *data)
{
  for (int64_t r = 0; r <= nrows; ++r)
    indptr[r] = 0;
  int64_t cmin = 0, cmax = -1;
  for (int64_t e = 0; e < n; ++e)
  {
    if (rows[e] < 0 || rows[e] >= nrows)
      return -1;
    indptr[rows[e] + 1]++;
    if (e == 0 || cols[e] < cmin)
      cmin = cols[e];
    if (cols[e] > cmax)
      cmax = cols[e];
  }
  for (int64_t r = 0; r < nrows; ++r)
    indptr[r + 1] += indptr[r];
  /* Scatter into row buckets (indptr[r] advances to the bucket's end, then is shifted back). */
  for (int64_t e = 0; e < n; ++e)
  {
    int64_t k = indptr[rows[e]]++;
    indices[k] = cols[e];
    data[k] = values[e];
  }
  for (int64_t r = nrows; r > 0; --r)
    indptr[r] = indptr[r - 1];
  indptr[0] = 0;
  /* Where a column's entry of the current row went (a dense map over the columns' range,
   * when that range is not much larger than the entries): duplicates are summed in one
   * pass, and only the distinct columns of a row are sorted. */
  int64_t span = cmax - cmin + 1;
  int64_t *where = NULL;
  if (n > 0 && span <= 4 * n + 1024)
    where = (int64_t *)malloc((size_t)span * sizeof(int64_t));
  if (where)
    for (int64_t c = 0; c < span; ++c)
      where[c] = -1;
  int64_t out = 0;
  for (int64_t r = 0; r < nrows; ++r)
  {
    int64_t begin = indptr[r], end = indptr[r + 1];
    indptr[r] = out;
    if (where)
    {
      /* Compact in place (out <= a), summing into the first entry of each column. */
      for (int64_t a = begin; a < end; ++a)
      {
        int64_t c = indices[a] - cmin;
        int64_t k = where[c];
        if (k >= indptr[r])
          data[k] += data[a];
        else
        {
          where[c] = out;
          indices[out] = indices[a];
          data[out] = data[a];
          ++out;
        }
      }
      /* Sort the distinct columns (insertion sort: rows are short). */
      for (int64_t a = indptr[r] + 1; a < out; ++a)
      {
        int64_t c = indices[a];
        double v = data[a];
        int64_t b = a - 1;
        while (b >= indptr[r] && indices[b] > c)
        {
          indices[b + 1] = indices[b];
          data[b + 1] = data[b];
          --b;
        }
        indices[b + 1] = c;
        data[b + 1] = v;
      }
      continue;
    }
    for (int64_t a = begin + 1; a < end; ++a)
    {
      int64_t c = indices[a];
      double v = data[a];
      int64_t b = a - 1;
      while (b >= begin && indices[b] > c)
      {
        indices[b + 1] = indices[b];
        data[b + 1] = data[b];
        --b;
      }
      indices[b + 1] = c;
      data[b + 1] = v;
    }
    for (int64_t a = begin; a < end; ++a)
    {
      if (a > begin && indices[a] == indices[out - 1])
        data[out - 1] += data[a];
      else
      {
        indices[out] = indices[a];
        data[out] = data[a];
        ++out;
      }
    }
  }
  indptr[nrows] = out;
  free(where);
  return out;
}

/* Position in indices of each entry (rows[e], cols[e]) of a CSR structure with sorted
 * columns: a binary search in its row. -1 if an entry is not in the structure. */
int64_t s2s_csr_slots(const int64_t *indptr, const int64_t *indices, int64_t n,
                      const int64_t *rows, const int64_t *cols, int64_t *slots)
{
  for (int64_t e = 0; e < n; ++e)
  {
    int64_t lo = indptr[rows[e]], hi = indptr[rows[e] + 1], end = hi;
    while (lo < hi)
    {
      int64_t mid = lo + (hi - lo) / 2;
      if (indices[mid] < cols[e])
        lo = mid + 1;
      else
        hi = mid;
    }
    if (lo == end || indices[lo] != cols[e])
      return -1;
    slots[e] = lo;
  }
  return 0;
}

/* ---- Convex polygons in the plane (polygon.clip_convex, polygon.triangulate) ----------
 *
 * These reproduce the NumPy reference operation by operation, including the order of
 * its sums, so that both backends give the same vertices up to the last bit: a vertex
 * snapped onto an edge's line in one and not in the other would change the number of
 * vertices, not only their digits. */

/* Vertices of the working polygons: enough for convex polygons of up to 32 vertices in
 * all (each half-plane cut of a convex polygon adds at most one vertex); the Python
 * layer checks that bound. */
#define S2S_POLY_CAPACITY 64

/* sum a[0] + ... + a[n - 1] as NumPy's add.reduce sums a contiguous array: in order
 * below 8 terms, else in 8 interleaved partial sums (pairwise_sum, n <= 128 here). */
static double s2s_numpy_sum(const double *a, int n)
{
  if (n < 8)
  {
    double s = 0.0;
    for (int i = 0; i < n; ++i)
      s += a[i];
    return s;
  }
  double r[8];
  for (int j = 0; j < 8; ++j)
    r[j] = a[j];
  int i = 8;
  for (; i < n - (n % 8); i += 8)
    for (int j = 0; j < 8; ++j)
      r[j] += a[i + j];
  double s = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
  for (; i < n; ++i)
    s += a[i];
  return s;
}

/* Signed area of polygon v (n vertices, x y interleaved), positive counter-clockwise:
 * the terms x_i y_{i+1} - x_{i+1} y_i summed as polygon._signed_area sums them. */
static double s2s_signed_area(const double *v, int n)
{
  double t[S2S_POLY_CAPACITY];
  for (int i = 0; i < n; ++i)
  {
    int j = (i + 1) % n;
    t[i] = v[2 * i] * v[2 * j + 1] - v[2 * j] * v[2 * i + 1];
  }
  return 0.5 * s2s_numpy_sum(t, n);
}

static void s2s_reverse(double *v, int n)
{
  for (int i = 0, j = n - 1; i < j; ++i, --j)
  {
    double x = v[2 * i], y = v[2 * i + 1];
    v[2 * i] = v[2 * j];
    v[2 * i + 1] = v[2 * j + 1];
    v[2 * j] = x;
    v[2 * j + 1] = y;
  }
}

/* max(size, v) as NumPy's max: a NaN wins (so that, as in the reference, a NaN vertex
 * makes the tolerance NaN and the overlap empty; fmax would drop it). */
static double s2s_max_nan(double size, double v)
{
  return (v > size || isnan(v)) ? v : size;
}

/* Mean of n vertices as NumPy's mean(axis=0): summed row after row, then divided. */
static void s2s_vertex_mean(const double *v, int n, double *c)
{
  double x = 0.0, y = 0.0;
  for (int i = 0; i < n; ++i)
  {
    x += v[2 * i];
    y += v[2 * i + 1];
  }
  c[0] = x / n;
  c[1] = y / n;
}

/* The overlap of convex polygons s (ns vertices) and c (nc vertices) into out; returns
 * its number of vertices, 0 if empty, -1 if it has more than `width` vertices or a cut
 * would exceed the working capacity (the polygons are not convex). */
static int s2s_clip_one(const double *s, int ns, const double *c, int nc, double round_off,
                        int width, double *out)
{
  /* Two working polygons, cut from one into the other. */
  double buf[2][2 * S2S_POLY_CAPACITY], clip[2 * S2S_POLY_CAPACITY];
  double d[S2S_POLY_CAPACITY];
  if (ns < 3 || nc < 3)
    return 0;
  double centre[2];
  s2s_vertex_mean(c, nc, centre);
  double size = 0.0;
  double *poly = buf[0], *next = buf[1];
  for (int i = 0; i < ns; ++i)
    for (int g = 0; g < 2; ++g)
    {
      poly[2 * i + g] = s[2 * i + g] - centre[g];
      size = s2s_max_nan(size, fabs(poly[2 * i + g]));
    }
  for (int i = 0; i < nc; ++i)
    for (int g = 0; g < 2; ++g)
    {
      clip[2 * i + g] = c[2 * i + g] - centre[g];
      size = s2s_max_nan(size, fabs(clip[2 * i + g]));
    }
  const double tol = round_off * size;
  if (s2s_signed_area(poly, ns) < 0.0)
    s2s_reverse(poly, ns);
  if (s2s_signed_area(clip, nc) < 0.0)
    s2s_reverse(clip, nc);
  if (!(s2s_signed_area(clip, nc) > tol * size))
    return 0;
  int n = ns;
  for (int k = 0; k < nc; ++k)
  {
    const double *a = clip + 2 * k, *b = clip + 2 * ((k + 1) % nc);
    double e0 = b[0] - a[0], e1 = b[1] - a[1];
    double length = hypot(e0, e1);
    if (length <= tol)
      continue;
    int inside = 0, outside = 0;
    for (int i = 0; i < n; ++i)
    {
      double di = (e0 * (poly[2 * i + 1] - a[1]) - e1 * (poly[2 * i] - a[0])) / length;
      /* Within round-off of the edge's line: on it, so shared edges leave no sliver. */
      if (fabs(di) <= tol)
        di = 0.0;
      d[i] = di;
      inside |= di > 0.0;
      outside |= di < 0.0;
    }
    if (!inside)
      return 0;
    if (!outside)
      continue;
    int m = 0;
    for (int i = 0; i < n; ++i)
    {
      int j = (i + 1) % n;
      int crossing = (d[i] > 0.0 && d[j] < 0.0) || (d[i] < 0.0 && d[j] > 0.0);
      if (m + (d[i] >= 0.0) + crossing > S2S_POLY_CAPACITY)
        return -1;
      if (d[i] >= 0.0)
      {
        next[2 * m] = poly[2 * i];
        next[2 * m + 1] = poly[2 * i + 1];
        ++m;
      }
      if (crossing)
      {
        double t = d[i] / (d[i] - d[j]);
        next[2 * m] = poly[2 * i] + t * (poly[2 * j] - poly[2 * i]);
        next[2 * m + 1] = poly[2 * i + 1] + t * (poly[2 * j + 1] - poly[2 * i + 1]);
        ++m;
      }
    }
    double *swap = poly;
    poly = next;
    next = swap;
    n = m;
  }
  /* Merge coinciding consecutive vertices, each compared with its predecessor in the
   * polygon before merging (as the reference's vectorized test does). */
  int m = 0;
  for (int i = 0; i < n; ++i)
  {
    int h = (i + n - 1) % n;
    double dx = poly[2 * i] - poly[2 * h], dy = poly[2 * i + 1] - poly[2 * h + 1];
    if (sqrt(dx * dx + dy * dy) > tol)
    {
      next[2 * m] = poly[2 * i];
      next[2 * m + 1] = poly[2 * i + 1];
      ++m;
    }
  }
  if (m < 3 || !(s2s_signed_area(next, m) > tol * size))
    return 0;
  if (m > width)
    return -1;
  for (int i = 0; i < m; ++i)
  {
    out[2 * i] = next[2 * i] + centre[0];
    out[2 * i + 1] = next[2 * i + 1] + centre[1];
  }
  return m;
}

int s2s_clip_polygons(const double *subject, int ms, const int32_t *subject_counts,
                      const double *clip, int mc, const int32_t *clip_counts, int P,
                      double round_off, int width, double *out, int32_t *counts)
{
  int failed = 0;
  for (int p = 0; p < P; ++p)
  {
    double *o = out + (int64_t)p * width * 2;
    for (int i = 0; i < 2 * width; ++i)
      o[i] = 0.0;
    counts[p] = s2s_clip_one(subject + (int64_t)p * ms * 2, subject_counts[p],
                             clip + (int64_t)p * mc * 2, clip_counts[p], round_off, width, o);
    if (counts[p] < 0)
    {
      for (int i = 0; i < 2 * width; ++i)
        o[i] = 0.0;
      ++failed;
    }
  }
  return failed;
}

int64_t s2s_triangulate_polygons(const double *polygons, int m, const int32_t *counts, int P,
                                 double round_off, double *triangles, int32_t *owner)
{
  int64_t T = 0;
  double rel[2 * S2S_POLY_CAPACITY];
  for (int p = 0; p < P; ++p)
  {
    const double *v = polygons + (int64_t)p * m * 2;
    int n = counts[p];
    if (n < 3)
      continue;
    double centre[2], size = 0.0;
    s2s_vertex_mean(v, n, centre);
    for (int i = 0; i < 2 * n; ++i)
    {
      rel[i] = v[i] - centre[i % 2];
      size = s2s_max_nan(size, fabs(rel[i]));
    }
    /* pow, as NumPy's scalar size**2, not size * size: the same rounding as the reference. */
    const double flat = round_off * pow(size, 2.0);
    for (int i = 0; i < n; ++i)
    {
      const double *a = rel + 2 * i, *b = rel + 2 * ((i + 1) % n);
      /* Fan triangles on edges of round-off length (repeated vertices) are flat. */
      if (!(0.5 * (a[0] * b[1] - a[1] * b[0]) > flat))
        continue;
      double *t = triangles + T * 6;
      t[0] = 0.0 + centre[0];
      t[1] = 0.0 + centre[1];
      t[2] = a[0] + centre[0];
      t[3] = a[1] + centre[1];
      t[4] = b[0] + centre[0];
      t[5] = b[1] + centre[1];
      owner[T++] = p;
    }
  }
  return T;
}

/* The pairs of overlapping boxes among the sweep's candidates (search.box_pairs): box i
 * of a (na, 2, gdim) against the boxes order[start[i]], ..., order[stop[i] - 1] of b,
 * in that order; writes (ia, ib) and returns their number. */
int64_t s2s_box_overlaps(const double *a, int64_t na, const double *b, int gdim,
                         const int64_t *order, const int64_t *start, const int64_t *stop,
                         int32_t *ia, int32_t *ib)
{
  int64_t n = 0;
  for (int64_t i = 0; i < na; ++i)
  {
    const double *lo = a + 2 * gdim * i, *hi = lo + gdim;
    for (int64_t k = start[i]; k < stop[i]; ++k)
    {
      const int64_t j = order[k];
      const double *blo = b + 2 * gdim * j, *bhi = blo + gdim;
      int overlap = 1;
      for (int d = 0; d < gdim; ++d)
        overlap &= (lo[d] <= bhi[d]) & (blo[d] <= hi[d]);
      if (overlap)
        ia[n] = (int32_t)i, ib[n++] = (int32_t)j;
    }
  }
  return n;
}
