/*
 * Small dense matrices pointwise: the identity, the guarded inverse, a
 * symmetric eigen-decomposition and the CSPH correction built on them.
 *
 * Written in the common subset of C11 and OpenCL C (scalars only), like
 * material_models.cl, so the unit tests compile this very file on the host
 * (tests/test_matrix.c, in 2-D and 3-D). Matrices are real[3][3]; only the
 * first SPH_DIM rows and columns are read, the rest is left as the
 * identity's.
 */
#ifndef SPH_MATRIX_CL
#define SPH_MATRIX_CL

#ifndef SPH_DIM
#error "SPH_DIM must be defined (2 or 3)"
#endif

static inline void matrix_identity(real c[3][3])
{
    for (int a = 0; a < 3; ++a)
        for (int e = 0; e < 3; ++e)
            c[a][e] = a == e ? (real)1 : (real)0;
}

/* Determinants of the leading 2 x 2 and the whole 3 x 3 of a. */
static inline real determinant2(real a[3][3])
{
    return a[0][0] * a[1][1] - a[0][1] * a[1][0];
}

static inline real determinant3(real a[3][3])
{
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/* Inverse of a dim x dim matrix whose determinant is near 1 (a CSPH moment
 * matrix, a deformation gradient); falls back to the identity, and returns
 * 0, when the determinant is below 1/32 (2-D) or 1/1024 (3-D). A moment
 * matrix B = sum_j V_j x_ji (x) grad W is I inside a body; on a regular
 * lattice's flat face, edge and corner its determinant is 0.37 / 0.31,
 * 0.095, 0.028 (2-D / 3-D face, 3-D edge, 3-D corner; 2-D corner 0.14;
 * Wendland C2, h = 1.2 dx; tests/test_matrix.c prints them). A smaller one
 * is a neighbourhood that does not determine a gradient (spray and debris
 * with a few neighbours, a line of particles), and its inverse would
 * multiply that neighbourhood's velocity differences by up to 1 / det. With
 * a 1e-3 threshold a debris particle at a cavity's lip was compressed to
 * 1.5 rho0 within a few steps (gelatin, d/dx = 8, energy drift 0.51); with
 * this one the run's drift is 0.07. */
static inline int matrix_invert_or_identity(real b[3][3], real c[3][3])
{
    matrix_identity(c);
#if SPH_DIM == 2
    const real det = determinant2(b);
    if (fabs(det) < (real)(1.0 / 32.0))
        return 0;
    c[0][0] = b[1][1] / det;
    c[0][1] = -b[0][1] / det;
    c[1][0] = -b[1][0] / det;
    c[1][1] = b[0][0] / det;
#else
    const real det = determinant3(b);
    if (fabs(det) < (real)(1.0 / 1024.0))
        return 0;
    const real inv = (real)1 / det;
    c[0][0] = (b[1][1] * b[2][2] - b[1][2] * b[2][1]) * inv;
    c[0][1] = (b[0][2] * b[2][1] - b[0][1] * b[2][2]) * inv;
    c[0][2] = (b[0][1] * b[1][2] - b[0][2] * b[1][1]) * inv;
    c[1][0] = (b[1][2] * b[2][0] - b[1][0] * b[2][2]) * inv;
    c[1][1] = (b[0][0] * b[2][2] - b[0][2] * b[2][0]) * inv;
    c[1][2] = (b[0][2] * b[1][0] - b[0][0] * b[1][2]) * inv;
    c[2][0] = (b[1][0] * b[2][1] - b[1][1] * b[2][0]) * inv;
    c[2][1] = (b[0][1] * b[2][0] - b[0][0] * b[2][1]) * inv;
    c[2][2] = (b[0][0] * b[1][1] - b[0][1] * b[1][0]) * inv;
#endif
    return 1;
}

/* Whether every eigenvalue of the symmetric matrix b exceeds f: b - f I is
 * positive definite, i.e. its leading principal minors are all positive
 * (Sylvester's criterion). A few products, no decomposition. */
static inline int symmetric_eigenvalues_above(real b[3][3], real f)
{
    real a[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            a[i][j] = b[i][j] - (i == j ? f : (real)0);
#if SPH_DIM == 2
    return a[0][0] > 0 && determinant2(a) > 0;
#else
    return a[0][0] > 0 && determinant2(a) > 0 && determinant3(a) > 0;
#endif
}

/* Eigen-decomposition of a symmetric 3 x 3 by cyclic Jacobi rotations
 * (Golub & Van Loan, Matrix Computations, 4th ed. 2013, sec. 8.5.2-8.5.3);
 * on return t is diagonal (the eigenvalues) and v holds the eigenvectors
 * as columns. Six sweeps reach float round-off for any input. Artificial
 * stress (material.cl) and the CSPH correction use it. */
static inline void symmetric_eigen(real t[3][3], real v[3][3])
{
    matrix_identity(v);
    for (int sweep = 0; sweep < 6; ++sweep)
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (fabs(t[p][q]) < (real)1e-30)
                    continue;
                const real theta = (t[q][q] - t[p][p]) / ((real)2 * t[p][q]);
                const real tan_phi = (theta >= 0 ? (real)1 : (real)-1) /
                                     (fabs(theta) + sqrt(theta * theta + (real)1));
                const real c = (real)1 / sqrt(tan_phi * tan_phi + (real)1), s = tan_phi * c;
                for (int k = 0; k < 3; ++k) { /* t <- t J */
                    const real tkp = t[k][p], tkq = t[k][q];
                    t[k][p] = c * tkp - s * tkq;
                    t[k][q] = s * tkp + c * tkq;
                }
                for (int k = 0; k < 3; ++k) { /* t <- J^T t */
                    const real tpk = t[p][k], tqk = t[q][k];
                    t[p][k] = c * tpk - s * tqk;
                    t[q][k] = s * tpk + c * tqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const real vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
}

/* The smallest eigenvalue a CSPH moment matrix's inverse uses: 1/10, so
 * the correction amplifies a gradient at most tenfold along any direction.
 * Every regular lattice's face, edge and corner lies above it: the 3-D
 * corner's smallest eigenvalue over the six smoothing kernels at h = 1-2 dx
 * is 0.11 (Gaussian and quintic spline at 2 dx) to 0.32, 0.24 for Wendland
 * C2 at 1.2 dx; the 2-D corner's 0.17-0.36 (tests/test_matrix.c checks
 * and prints them). So it leaves a body's corners as they were; what
 * falls below is a deformed or torn neighbourhood that is nearly flat or
 * nearly a line. Such a matrix can pass the determinant guard with one
 * small eigenvalue: a SEBS particle splashed above the target's
 * face had det 6.2e-3 and smallest eigenvalue 0.056, an 18-fold
 * amplification, before the 3-D run at d/dx 12 burst next to it
 * (docs/validation_penetration.md, session 34). */
#define CSPH_EIGENVALUE_FLOOR ((real)0.1)

/* The CSPH correction C of a moment matrix B (thesis eqs. 3.10-3.11):
 * B^-1, the identity where the determinant guard fails
 * (matrix_invert_or_identity), and where B has an eigenvalue below
 * CSPH_EIGENVALUE_FLOOR the inverse with those eigenvalues raised to the
 * floor, Q diag(1 / max(lambda_k, floor)) Q^T: continuous in B (it is
 * B^-1 at the floor), and B^-1 to the bit wherever every eigenvalue is
 * above it. B is symmetric (grad W_ij is along x_ij); its rounding
 * asymmetry is averaged out before the decomposition. */
static inline void csph_correction(real b[3][3], real c[3][3])
{
    if (!matrix_invert_or_identity(b, c) || symmetric_eigenvalues_above(b, CSPH_EIGENVALUE_FLOOR))
        return;
    real t[3][3], v[3][3];
    for (int p = 0; p < 3; ++p)
        for (int r = 0; r < 3; ++r)
            t[p][r] = p < SPH_DIM && r < SPH_DIM ? (real)0.5 * (b[p][r] + b[r][p]) : (real)0;
    symmetric_eigen(t, v);
    for (int p = 0; p < SPH_DIM; ++p)
        for (int r = 0; r < SPH_DIM; ++r) {
            real sum = 0;
            for (int k = 0; k < SPH_DIM; ++k)
                sum += v[p][k] * v[r][k] / fmax(t[k][k], CSPH_EIGENVALUE_FLOOR);
            c[p][r] = sum;
        }
}

#endif /* SPH_MATRIX_CL */
