/* Copyright (C) 2026 dolfinx_contact_s2s developers
 * SPDX-License-Identifier: MIT
 *
 * Declarations of the compiled contact kernels (_kernels.c, _faces.c), read by CFFI's
 * cdef in c_backend.py: what Python may call.
 */
void s2s_facet_coefficients(const double *basis, int M, int K, const int32_t *local_facet,
                            int F, const double *coords, int gdim, double *out);
void s2s_evaluate(const double *c, int M, const int32_t *rows, const double *xi, int P,
                  double *x, double *dx, double *ddx);
void s2s_facet_basis(const double *table, int M, int K, const int32_t *local_facet,
                     const double *xi, int P, double *out);
void s2s_cell_normals(const double *tables, const double *coords, int P, int K,
                      const double *reference_normals, double *out);
void s2s_outward_normals(const double *c, int M, const double *orientation,
                         const int32_t *rows, const double *xi, int P, double *out);
void s2s_project(const double *c, int M, const int32_t *rows, const double *points, int P,
                 int iterations, double tol, double *xi);
void s2s_intersect(const double *c, int M, const int32_t *rows, const double *origins,
                   const double *directions, int P, int iterations, double tol, double *eta);
void s2s_segment_to_segment(const double *mu, const double *phi_c, const double *phi_t,
                            const double *normals, const double *weights, const double *gaps,
                            int S, int Q, int nk, int nc, int nt, int gdim, double *b_c,
                            double *b_t, double *g);
void s2s_edge_coupling(const double *cc, int Mc, const double *c_orientation, const double *tc,
                       int Mt, const int32_t *gc, const int32_t *gt, int S, int Q,
                       const double *xi, const double *weights, const double *mu_table, int Mm,
                       int nk, const int8_t *flip, const double *c_table, int Mp, int nc,
                       const int32_t *lf_c, const double *t_table, int Mq, int nt,
                       const int32_t *lf_t, int tangent, int square, int iterations, double tol,
                       double *b_c, double *b_t, double *g, double *sig, double *cov);
void s2s_clip_segments(const double *cc, int Mc, const double *c_orientation,
                       const double *tc, int Mt, const double *t_orientation,
                       const int32_t *ic, const int32_t *it, int N, double radius,
                       double min_length, double round_off, int iterations, double tol,
                       double *lo, double *hi, int8_t *keep);
void s2s_bounding_boxes(const double *c, int M, int F, int samples, double pad, double *out);
int64_t s2s_box_overlaps(const double *a, int64_t na, const double *b, int gdim,
                         const int64_t *order, const int64_t *start, const int64_t *stop,
                         int32_t *ia, int32_t *ib);
int64_t s2s_coo_to_csr(int64_t nrows, int64_t n, const int64_t *rows, const int64_t *cols,
                       const double *values, int64_t *indptr, int64_t *indices, double *data);
int64_t s2s_csr_slots(const int64_t *indptr, const int64_t *indices, int64_t n,
                      const int64_t *rows, const int64_t *cols, int64_t *slots);
int s2s_clip_polygons(const double *subject, int ms, const int32_t *subject_counts,
                      const double *clip, int mc, const int32_t *clip_counts, int P,
                      double round_off, int width, double *out, int32_t *counts);
int64_t s2s_triangulate_polygons(const double *polygons, int m, const int32_t *counts, int P,
                                 double round_off, double *triangles, int32_t *owner);
void s2s_face_evaluate(const double *nodes, int K, const int32_t *rows, const double *xi, int P,
                       double *x, double *dx);
void s2s_face_intersect(const double *nodes, int K, const int32_t *rows, const double *origins,
                        const double *directions, int P, int iterations, double tol,
                        double round_off, double *xi, double *t, int8_t *ok);
void s2s_face_coupling(const double *c_nodes, int Kc, const double *c_orientation,
                       const double *t_nodes, int Kt, const int32_t *rows_c,
                       const int32_t *rows_t, const double *xi, const double *weights, int S,
                       int Q, const double *mu_coef, int Mm, int nk, const int32_t *mu_index,
                       const double *c_coef, int Mc, int nc, const int32_t *c_index,
                       const double *t_coef, int Mt, int nt, const int32_t *t_index,
                       int square, int iterations, double tol, double round_off,
                       double zero_below, const double *axis, int which, double *b_c,
                       double *b_t, double *g, double *coverage, int8_t *ok);
void s2s_face_piece_gaps(const double *c_nodes, int Kc, const double *c_orientation,
                         const double *t_nodes, int Kt, const int32_t *rows_c,
                         const int32_t *rows_t, const double *triangles, const double *origin,
                         const double *frame, int S, int iterations, double tol,
                         double round_off, double *gap, int8_t *ok_c, int8_t *ok_t);
void s2s_face_piece_points(const double *nodes, int K, const int32_t *rows,
                           const double *triangles, const double *origin, const double *frame,
                           int S, const double *X, const double *W, int Q, int iterations,
                           double tol, double round_off, double *xi, double *weights,
                           int8_t *ok);
void s2s_face_project(const double *c_nodes, int Kc, const double *c_orientation,
                      const double *t_nodes, int Kt, const double *t_orientation,
                      const int32_t *ic, const int32_t *it, int N, double round_off,
                      double *origin, double *frame, double *c_poly, double *t_poly,
                      int8_t *facing, int8_t *ok_c, int8_t *ok_t);
