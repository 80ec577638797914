//! LU with partial pivoting for small dense matrices, real and complex, where faer's blocked kernels cost more
//! than the arithmetic (measured: on ROBER's 3x3 system they took over half of Rodas4's time). Column-major
//! storage; a complex matrix is held as separate real and imaginary parts. Sizes 1 to 8 are unrolled.

/// Largest dimension factored here; larger dense matrices go to faer.
pub(crate) const SMALL: usize = 16;

/// Calls `$kernel::<$arith>(args.., n)` with n as a literal for n = 1..=8, so that each small size gets its own
/// fully unrolled copy, and with the run-time n otherwise.
macro_rules! unrolled {
    ($kernel:ident::<$arith:ty>($($arg:expr),*; $n:expr)) => {
        match $n {
            1 => $kernel::<$arith>($($arg,)* 1),
            2 => $kernel::<$arith>($($arg,)* 2),
            3 => $kernel::<$arith>($($arg,)* 3),
            4 => $kernel::<$arith>($($arg,)* 4),
            5 => $kernel::<$arith>($($arg,)* 5),
            6 => $kernel::<$arith>($($arg,)* 6),
            7 => $kernel::<$arith>($($arg,)* 7),
            8 => $kernel::<$arith>($($arg,)* 8),
            n => $kernel::<$arith>($($arg,)* n),
        }
    };
}

/// How `c - a b` is computed: separately rounded, or fused (one instruction on CPUs with FMA).
trait Arith {
    fn mul_sub(a: f64, b: f64, c: f64) -> f64;
}

struct Plain;
impl Arith for Plain {
    #[inline(always)]
    fn mul_sub(a: f64, b: f64, c: f64) -> f64 {
        c - a * b
    }
}

struct Fused;
impl Arith for Fused {
    #[inline(always)]
    fn mul_sub(a: f64, b: f64, c: f64) -> f64 {
        (-a).mul_add(b, c)
    }
}

/// Whether this CPU has AVX2 and FMA: the kernels then run a copy compiled for them (detected once at run time,
/// so the library stays portable; results differ from the portable copy in the last bits only).
#[inline]
fn fused() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("fma") && std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Defines a public kernel that dispatches to a copy compiled for AVX2 + FMA when the CPU has them.
macro_rules! dispatch {
    ($(#[$doc:meta])* fn $name:ident => $generic:ident ( $($arg:ident : $ty:ty),* ) $(-> $ret:ty)?) => {
        $(#[$doc])*
        #[allow(clippy::too_many_arguments)]
        pub(crate) fn $name($($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2,fma")]
                unsafe fn with_fma($($arg: $ty),*) $(-> $ret)? {
                    $generic::<Fused>($($arg),*)
                }
                if fused() {
                    // SAFETY: the CPU was just checked for AVX2 and FMA.
                    return unsafe { with_fma($($arg),*) };
                }
            }
            $generic::<Plain>($($arg),*)
        }
    };
}

dispatch! {
    /// Factors the column-major n x n matrix `a` in place (unit lower L below the diagonal, U on and above),
    /// recording row interchanges in `piv` and the reciprocals of U's diagonal in `inv_diag`. Returns false if a
    /// pivot is zero or not finite.
    fn factor => factor_any(a: &mut [f64], piv: &mut [usize], inv_diag: &mut [f64], n: usize) -> bool
}

#[inline(always)]
fn factor_any<A: Arith>(a: &mut [f64], piv: &mut [usize], inv_diag: &mut [f64], n: usize) -> bool {
    // A constant n lets the compiler unroll the loops completely (tiny loops are otherwise dominated by the
    // bookkeeping of vectorised loops and their remainders).
    unrolled!(factor_n::<A>(a, piv, inv_diag; n))
}

#[inline(always)]
fn factor_n<A: Arith>(a: &mut [f64], piv: &mut [usize], inv_diag: &mut [f64], n: usize) -> bool {
    let (a, piv, inv_diag) = (&mut a[..n * n], &mut piv[..n], &mut inv_diag[..n]);
    for k in 0..n {
        let col = k * n;
        let mut p = k;
        let mut best = a[col + k].abs();
        for i in k + 1..n {
            let v = a[col + i].abs();
            if v > best {
                best = v;
                p = i;
            }
        }
        if !(best > 0.0 && best.is_finite()) {
            return false;
        }
        piv[k] = p;
        if p != k {
            for j in 0..n {
                a.swap(j * n + k, j * n + p);
            }
        }
        let inv = 1.0 / a[col + k];
        inv_diag[k] = inv;
        for i in k + 1..n {
            a[col + i] *= inv;
        }
        for j in k + 1..n {
            // No test for akj == 0: for small n a mispredicted branch costs more than the arithmetic it saves.
            let akj = a[j * n + k];
            for i in k + 1..n {
                a[j * n + i] = A::mul_sub(a[col + i], akj, a[j * n + i]);
            }
        }
    }
    true
}

dispatch! {
    /// Solves A x = b in place with the factors from [`factor`].
    fn solve => solve_any(a: &[f64], piv: &[usize], inv_diag: &[f64], b: &mut [f64], n: usize)
}

#[inline(always)]
fn solve_any<A: Arith>(a: &[f64], piv: &[usize], inv_diag: &[f64], b: &mut [f64], n: usize) {
    unrolled!(solve_n::<A>(a, piv, inv_diag, b; n))
}

#[inline(always)]
fn solve_n<A: Arith>(a: &[f64], piv: &[usize], inv_diag: &[f64], b: &mut [f64], n: usize) {
    let (a, piv, inv_diag, b) = (&a[..n * n], &piv[..n], &inv_diag[..n], &mut b[..n]);
    for k in 0..n {
        b.swap(k, piv[k]);
    }
    for k in 0..n {
        let bk = b[k];
        for i in k + 1..n {
            b[i] = A::mul_sub(a[k * n + i], bk, b[i]);
        }
    }
    for k in (0..n).rev() {
        b[k] *= inv_diag[k];
        let bk = b[k];
        for i in 0..k {
            b[i] = A::mul_sub(a[k * n + i], bk, b[i]);
        }
    }
}

dispatch! {
    /// Factors the complex column-major n x n matrix (re + i im) in place, as [`factor`] does for real matrices;
    /// `inv_re`, `inv_im` receive the reciprocals of U's diagonal.
    fn factor_complex => factor_complex_any(
        re: &mut [f64], im: &mut [f64], piv: &mut [usize], inv_re: &mut [f64], inv_im: &mut [f64], n: usize
    ) -> bool
}

#[inline(always)]
fn factor_complex_any<A: Arith>(
    re: &mut [f64],
    im: &mut [f64],
    piv: &mut [usize],
    inv_re: &mut [f64],
    inv_im: &mut [f64],
    n: usize,
) -> bool {
    unrolled!(factor_complex_n::<A>(re, im, piv, inv_re, inv_im; n))
}

#[inline(always)]
fn factor_complex_n<A: Arith>(
    re: &mut [f64],
    im: &mut [f64],
    piv: &mut [usize],
    inv_re: &mut [f64],
    inv_im: &mut [f64],
    n: usize,
) -> bool {
    let (re, im) = (&mut re[..n * n], &mut im[..n * n]);
    let (piv, inv_re, inv_im) = (&mut piv[..n], &mut inv_re[..n], &mut inv_im[..n]);
    for k in 0..n {
        let col = k * n;
        let mut p = k;
        let mut best = re[col + k] * re[col + k] + im[col + k] * im[col + k];
        for i in k + 1..n {
            let v = re[col + i] * re[col + i] + im[col + i] * im[col + i];
            if v > best {
                best = v;
                p = i;
            }
        }
        if !(best > 0.0 && best.is_finite()) {
            return false;
        }
        piv[k] = p;
        if p != k {
            for j in 0..n {
                re.swap(j * n + k, j * n + p);
                im.swap(j * n + k, j * n + p);
            }
        }
        let (dr, di) = (re[col + k], im[col + k]);
        let d = dr * dr + di * di;
        let (ir, ii) = (dr / d, -di / d);
        inv_re[k] = ir;
        inv_im[k] = ii;
        for i in k + 1..n {
            let (a, b) = (re[col + i], im[col + i]);
            re[col + i] = a * ir - b * ii;
            im[col + i] = a * ii + b * ir;
        }
        for j in k + 1..n {
            let (ar, ai) = (re[j * n + k], im[j * n + k]);
            for i in k + 1..n {
                let (lr, li) = (re[col + i], im[col + i]);
                re[j * n + i] = A::mul_sub(lr, ar, A::mul_sub(-li, ai, re[j * n + i]));
                im[j * n + i] = A::mul_sub(lr, ai, A::mul_sub(li, ar, im[j * n + i]));
            }
        }
    }
    true
}

dispatch! {
    /// Solves (re + i im) x = b in place, b = br + i bi, with the factors from [`factor_complex`].
    fn solve_complex => solve_complex_any(
        re: &[f64], im: &[f64], piv: &[usize], inv_re: &[f64], inv_im: &[f64], br: &mut [f64], bi: &mut [f64],
        n: usize
    )
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn solve_complex_any<A: Arith>(
    re: &[f64],
    im: &[f64],
    piv: &[usize],
    inv_re: &[f64],
    inv_im: &[f64],
    br: &mut [f64],
    bi: &mut [f64],
    n: usize,
) {
    unrolled!(solve_complex_n::<A>(re, im, piv, inv_re, inv_im, br, bi; n))
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn solve_complex_n<A: Arith>(
    re: &[f64],
    im: &[f64],
    piv: &[usize],
    inv_re: &[f64],
    inv_im: &[f64],
    br: &mut [f64],
    bi: &mut [f64],
    n: usize,
) {
    let (re, im, piv) = (&re[..n * n], &im[..n * n], &piv[..n]);
    let (inv_re, inv_im, br, bi) = (&inv_re[..n], &inv_im[..n], &mut br[..n], &mut bi[..n]);
    for k in 0..n {
        br.swap(k, piv[k]);
        bi.swap(k, piv[k]);
    }
    for k in 0..n {
        let (xr, xi) = (br[k], bi[k]);
        for i in k + 1..n {
            let (lr, li) = (re[k * n + i], im[k * n + i]);
            br[i] = A::mul_sub(lr, xr, A::mul_sub(-li, xi, br[i]));
            bi[i] = A::mul_sub(lr, xi, A::mul_sub(li, xr, bi[i]));
        }
    }
    for k in (0..n).rev() {
        let (xr, xi) = (br[k], bi[k]);
        let (xr, xi) = (xr * inv_re[k] - xi * inv_im[k], xr * inv_im[k] + xi * inv_re[k]);
        br[k] = xr;
        bi[k] = xi;
        for i in 0..k {
            let (ur, ui) = (re[k * n + i], im[k * n + i]);
            br[i] = A::mul_sub(ur, xr, A::mul_sub(-ui, xi, br[i]));
            bi[i] = A::mul_sub(ur, xi, A::mul_sub(ui, xr, bi[i]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random 7x7 system: the solution's residual |A x - b| is at round-off level (1e-12 for entries O(1)).
    #[test]
    fn solves_a_random_system() {
        let n = 7;
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let a: Vec<f64> = (0..n * n).map(|_| rnd()).collect();
        let b: Vec<f64> = (0..n).map(|_| rnd()).collect();
        let (mut lu, mut piv, mut inv, mut x) = (a.clone(), vec![0; n], vec![0.0; n], b.clone());
        assert!(factor(&mut lu, &mut piv, &mut inv, n));
        solve(&lu, &piv, &inv, &mut x, n);
        for i in 0..n {
            let ax: f64 = (0..n).map(|j| a[j * n + i] * x[j]).sum();
            assert!((ax - b[i]).abs() < 1e-12, "row {i}: {ax} vs {}", b[i]);
        }
    }

    #[test]
    fn singular_matrix_is_detected() {
        let mut a = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!factor(&mut a, &mut [0, 0], &mut [0.0, 0.0], 2));
    }

    /// A random complex 6x6 system: residual at round-off level.
    #[test]
    fn solves_a_random_complex_system() {
        let n = 6;
        let mut seed = 777u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let (ar, ai): (Vec<f64>, Vec<f64>) = (0..n * n).map(|_| (rnd(), rnd())).unzip();
        let (br, bi): (Vec<f64>, Vec<f64>) = (0..n).map(|_| (rnd(), rnd())).unzip();
        let (mut lr, mut li, mut piv) = (ar.clone(), ai.clone(), vec![0; n]);
        let (mut vr, mut vi) = (vec![0.0; n], vec![0.0; n]);
        assert!(factor_complex(&mut lr, &mut li, &mut piv, &mut vr, &mut vi, n));
        let (mut xr, mut xi) = (br.clone(), bi.clone());
        solve_complex(&lr, &li, &piv, &vr, &vi, &mut xr, &mut xi, n);
        for i in 0..n {
            let (mut sr, mut si) = (0.0, 0.0);
            for j in 0..n {
                let (a, b) = (ar[j * n + i], ai[j * n + i]);
                sr += a * xr[j] - b * xi[j];
                si += a * xi[j] + b * xr[j];
            }
            assert!((sr - br[i]).abs() < 1e-12 && (si - bi[i]).abs() < 1e-12, "row {i}");
        }
    }
}
