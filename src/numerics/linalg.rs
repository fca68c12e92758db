//! Small dense linear algebra on row-major `f64` slices for the filter's inner loop.
//!
//! The filter works on a few dozen states at most; these loops are written so the compiler
//! vectorises the innermost one, and nothing allocates. The hottest kernels are compiled
//! twice on x86-64, for the baseline and for AVX2, and the AVX2 copy is used when the
//! processor has it ([`simd`]). Both copies do the same operations in the same order (no
//! fused multiply-add, fixed partial sums), so results are bit-identical either way: a test
//! per kernel (here and in `estimation::hybrid_ekf`) compares the two copies bit for bit.

/// out (r x c) = a (r x k) * b (k x c).
pub fn matmul(a: &[f64], b: &[f64], r: usize, k: usize, c: usize, out: &mut [f64]) {
    simd::dispatch!(matmul_impl(a, b, r, k, c, out))
}

/// P_il += c_i k_l - k_i row_l over the n x n matrix `p` (n = k.len()): the fused rank-two
/// form of a scalar Joseph update.
pub fn rank_two_update(p: &mut [f64], k: &[f64], c: &[f64], row: &[f64]) {
    simd::dispatch!(rank_two_update_impl(p, k, c, row))
}

#[inline(always)]
fn rank_two_update_impl(p: &mut [f64], k: &[f64], c: &[f64], row: &[f64]) {
    let n = k.len();
    let (c, row) = (&c[..n], &row[..n]);
    for (i, prow) in p[..n * n].chunks_exact_mut(n).enumerate() {
        let (ki, ci) = (k[i], c[i]);
        for l in 0..n {
            prow[l] += ci * k[l] - ki * row[l];
        }
    }
}

#[inline(always)]
fn matmul_impl(a: &[f64], b: &[f64], r: usize, k: usize, c: usize, out: &mut [f64]) {
    let (a, b, out) = (&a[..r * k], &b[..k * c], &mut out[..r * c]);
    out.fill(0.0);
    for (arow, orow) in a.chunks_exact(k).zip(out.chunks_exact_mut(c)) {
        for (&ail, brow) in arow.iter().zip(b.chunks_exact(c)) {
            axpy(ail, brow, orow);
        }
    }
}

/// x . y over equal-length slices, with four partial sums so that it vectorises.
#[inline]
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    let (x, y) = (&x[..n], &y[..n]);
    let mut acc = [0.0; 4];
    let mut i = 0;
    while i + 4 <= n {
        for l in 0..4 {
            acc[l] += x[i + l] * y[i + l];
        }
        i += 4;
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    while i < n {
        s += x[i] * y[i];
        i += 1;
    }
    s
}

/// sum x_i w_i y_i over equal-length slices (a weighted dot product), four partial sums.
#[inline]
pub fn dot3(x: &[f64], w: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len()).min(w.len());
    let (x, w, y) = (&x[..n], &w[..n], &y[..n]);
    let mut acc = [0.0; 4];
    let mut i = 0;
    while i + 4 <= n {
        for l in 0..4 {
            acc[l] += x[i + l] * w[i + l] * y[i + l];
        }
        i += 4;
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    while i < n {
        s += x[i] * w[i] * y[i];
        i += 1;
    }
    s
}

/// y += a x, for slices of equal length (written so that it vectorises).
#[inline(always)]
pub fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    let n = y.len().min(x.len());
    let (x, y) = (&x[..n], &mut y[..n]);
    for i in 0..n {
        y[i] += a * x[i];
    }
}

/// out (r x c) = a (r x k) * b^T where b is (c x k).
pub fn matmul_bt(a: &[f64], b: &[f64], r: usize, k: usize, c: usize, out: &mut [f64]) {
    for i in 0..r {
        let ai = &a[i * k..(i + 1) * k];
        for j in 0..c {
            let bj = &b[j * k..(j + 1) * k];
            out[i * c + j] = ai.iter().zip(bj).map(|(x, y)| x * y).sum();
        }
    }
}

/// Run-time choice between the baseline and the AVX2 build of a kernel.
mod simd {
    /// Calls `name(args)`, through its AVX2 build when the processor has AVX2.
    macro_rules! dispatch {
        ($name:ident($($arg:expr),*)) => {{
            #[cfg(target_arch = "x86_64")]
            {
                if std::is_x86_feature_detected!("avx2") {
                    #[target_feature(enable = "avx2")]
                    unsafe fn avx2(f: impl FnOnce()) {
                        f()
                    }
                    // SAFETY: the processor supports AVX2 (checked above); the closure is
                    // the safe baseline kernel, inlined into an AVX2-enabled function.
                    let mut result = None;
                    unsafe { avx2(|| result = Some($name($($arg),*))) };
                    return result.expect("the kernel ran");
                }
            }
            $name($($arg),*)
        }};
    }
    pub(crate) use dispatch;
}

pub(crate) use simd::dispatch;

/// In-place Cholesky factorisation of a symmetric positive-definite n x n matrix: the lower
/// triangle becomes L (A = L L^T), the strict upper triangle is zeroed. Returns the index of
/// the first pivot that is not positive, if any.
pub fn cholesky(a: &mut [f64], n: usize) -> Result<(), usize> {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if !(d > 0.0 && d.is_finite()) {
            return Err(j);
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
        for k in j + 1..n {
            a[j * n + k] = 0.0;
        }
    }
    Ok(())
}

/// Solves L L^T x = b in place for one right-hand side, with `l` from [`cholesky`].
pub fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}

/// Inverse of a symmetric positive-definite matrix from its Cholesky factor.
pub fn cholesky_inverse(l: &[f64], n: usize, out: &mut [f64]) {
    let mut col = vec![0.0; n];
    for j in 0..n {
        col.fill(0.0);
        col[j] = 1.0;
        cholesky_solve(l, n, &mut col);
        for i in 0..n {
            out[i * n + j] = col[i];
        }
    }
}

/// Replaces a square matrix by its symmetric part (P + P^T) / 2.
pub fn symmetrize(p: &mut [f64], n: usize) {
    for i in 0..n {
        for j in i + 1..n {
            let m = 0.5 * (p[i * n + j] + p[j * n + i]);
            p[i * n + j] = m;
            p[j * n + i] = m;
        }
    }
}

/// Test support for the kernels built twice (here and in `estimation::hybrid_ekf`): whether
/// the dispatch takes a different copy from the baseline one a test calls directly, seeded
/// inputs, and a bit-for-bit comparison.
#[cfg(test)]
pub(crate) mod simd_check {
    use rand::{rngs::StdRng, Rng, SeedableRng};

    /// Sizes of each dimension: 1 to 9 around the four partial sums and AVX2's four lanes,
    /// and larger odd and even ones (the filters have 2 to 29 states).
    pub(crate) const SIZES: [usize; 12] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 13, 16, 29];

    /// True when [`super::dispatch`] runs the AVX2 copy, so that comparing it with the baseline
    /// copy tests something; otherwise prints why the comparison is skipped.
    pub(crate) fn avx2_path_differs(kernel: &str) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            if cfg!(target_feature = "avx2") {
                eprintln!("{kernel}: skipped, this build targets AVX2 (RUSTFLAGS), so its baseline copy is AVX2 code too");
                false
            } else if std::is_x86_feature_detected!("avx2") {
                true
            } else {
                eprintln!("{kernel}: skipped, this processor has no AVX2 (the dispatch runs the baseline copy)");
                false
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            eprintln!("{kernel}: skipped, not x86-64 (one build of each kernel)");
            false
        }
    }

    /// A fixed-seed generator for a test's inputs.
    pub(crate) fn rng(seed: u64) -> StdRng {
        StdRng::seed_from_u64(seed)
    }

    /// `len` values of both signs spread over twelve decades (1e-6 to 1e6), so that sums
    /// round and their order matters.
    pub(crate) fn values(rng: &mut StdRng, len: usize) -> Vec<f64> {
        (0..len)
            .map(|_| rng.random_range(-1.0..1.0) * 10f64.powf(rng.random_range(-6.0..6.0)))
            .collect()
    }

    /// Asserts that two results are the same bits, naming the case and the first element
    /// that differs.
    pub(crate) fn assert_same_bits(avx2: &[f64], baseline: &[f64], case: &str) {
        assert_eq!(avx2.len(), baseline.len(), "{case}");
        for (i, (a, b)) in avx2.iter().zip(baseline).enumerate() {
            assert_eq!(
                a.to_bits(),
                b.to_bits(),
                "{case}, element {i}: AVX2 {a:e}, baseline {b:e}"
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solves_and_inverts() {
        let a = [4.0, 2.0, 0.6, 2.0, 5.0, 1.0, 0.6, 1.0, 3.0];
        let mut l = a;
        cholesky(&mut l, 3).unwrap();
        let mut x = [1.0, 2.0, 3.0];
        cholesky_solve(&l, 3, &mut x);
        let mut back = [0.0; 3];
        matmul(&a, &x, 3, 3, 1, &mut back);
        for (b, w) in back.iter().zip([1.0, 2.0, 3.0]) {
            assert!((b - w).abs() < 1e-12);
        }
        let mut inv = [0.0; 9];
        cholesky_inverse(&l, 3, &mut inv);
        let mut id = [0.0; 9];
        matmul(&a, &inv, 3, 3, 3, &mut id);
        for i in 0..3 {
            for j in 0..3 {
                let w = if i == j { 1.0 } else { 0.0 };
                assert!((id[i * 3 + j] - w).abs() < 1e-12);
            }
        }
    }

    /// matmul through the dispatch (AVX2 where the processor has it) against its baseline
    /// copy, bit for bit, over edge and odd sizes of each dimension.
    #[test]
    fn matmul_avx2_and_baseline_copies_agree_to_the_bit() {
        if !simd_check::avx2_path_differs("matmul") {
            return;
        }
        let mut rng = simd_check::rng(1);
        let mut cases = 0;
        for &r in &simd_check::SIZES {
            for &k in &simd_check::SIZES {
                for &c in &[1, 3, 4, 5, 8, 13, 29] {
                    let (a, b) = (
                        simd_check::values(&mut rng, r * k),
                        simd_check::values(&mut rng, k * c),
                    );
                    let (mut x, mut y) = (vec![f64::NAN; r * c], vec![f64::NAN; r * c]);
                    matmul(&a, &b, r, k, c, &mut x);
                    matmul_impl(&a, &b, r, k, c, &mut y);
                    simd_check::assert_same_bits(&x, &y, &format!("matmul {r}x{k}x{c}"));
                    cases += 1;
                }
            }
        }
        assert_eq!(cases, 12 * 12 * 7);
    }

    /// rank_two_update through the dispatch against its baseline copy, bit for bit.
    #[test]
    fn rank_two_update_avx2_and_baseline_copies_agree_to_the_bit() {
        if !simd_check::avx2_path_differs("rank_two_update") {
            return;
        }
        let mut rng = simd_check::rng(2);
        for &n in &simd_check::SIZES {
            let [k, c, row] = [(); 3].map(|_| simd_check::values(&mut rng, n));
            let p = simd_check::values(&mut rng, n * n);
            let (mut p1, mut p2) = (p.clone(), p);
            rank_two_update(&mut p1, &k, &c, &row);
            rank_two_update_impl(&mut p2, &k, &c, &row);
            simd_check::assert_same_bits(&p1, &p2, &format!("rank_two_update n = {n}"));
        }
    }

    #[test]
    fn cholesky_reports_an_indefinite_matrix() {
        let mut a = [1.0, 2.0, 2.0, 1.0];
        assert_eq!(cholesky(&mut a, 2), Err(1));
    }

    #[test]
    fn matmul_bt_is_a_times_b_transposed() {
        let a = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]; // 2x3
        let b = [1.0, 0.0, 1.0, 0.0, 1.0, 0.0]; // 2x3, b^T is 3x2
        let mut out = [0.0; 4];
        matmul_bt(&a, &b, 2, 3, 2, &mut out);
        assert_eq!(out, [4.0, 2.0, 10.0, 5.0]);
    }
}
