//! The dense solve of one Newton iteration: factorise the leading matrix f_q
//! (symmetric positive definite for linear elasticity) and solve, at the sizes of
//! the thesis scenes (6 to 60 coordinates). Candidates: faer's in-place partial-pivoting
//! LU (what `DenseLu` wraps), faer's in-place Cholesky (LLᵀ), nalgebra's Cholesky
//! (reusing its storage) and nalgebra's LU (allocates its permutation). An unblocked
//! left-looking Cholesky written by hand was measured too and lost to faer's at 12 to 60
//! coordinates (3.7 against 3.4 µs at 36, 12.0 against 8.1 µs at 60), so `DenseLlt` wraps faer.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::{Par, Spec};
use flexmbd_integrators::arrow_llt::ArrowLlt;
use flexmbd_integrators::lu::{DenseLlt, DenseLu};
use flexmbd_integrators::sparse_llt::SparseLlt;
use nalgebra::{DMatrix, DVector};

/// A symmetric positive definite test matrix like f_q: a mass-like diagonal plus a
/// penalty-like low-rank term.
fn spd(n: usize) -> DMatrix<f64> {
    let b = DMatrix::from_fn(n, n / 2 + 1, |i, j| ((i * 7 + j * 3) as f64 * 0.37).sin());
    DMatrix::from_diagonal_element(n, n, 1.0) + 1e4 * &b * b.transpose()
}

fn dense(c: &mut Criterion) {
    let mut g = c.benchmark_group("factor_solve");
    for n in [6usize, 12, 24, 36, 60] {
        let a = spd(n);
        let rhs = DVector::from_fn(n, |i, _| (i as f64).cos());
        let mut lu = DenseLu::new(n);
        let mut x = rhs.clone();
        g.bench_with_input(BenchmarkId::new("faer_lu_in_place", n), &n, |bch, _| {
            bch.iter(|| {
                lu.factor(&a).unwrap();
                x.copy_from(&rhs);
                lu.solve_in_place(&mut x);
            })
        });
        let mut l = a.clone();
        let mut buf = MemBuffer::new(llt::factor::cholesky_in_place_scratch::<f64>(
            n,
            Par::Seq,
            Spec::default(),
        ));
        g.bench_with_input(BenchmarkId::new("faer_llt_in_place", n), &n, |bch, _| {
            bch.iter(|| {
                l.copy_from(&a);
                let m = faer::MatMut::from_column_major_slice_mut(l.as_mut_slice(), n, n);
                llt::factor::cholesky_in_place(
                    m,
                    Default::default(),
                    Par::Seq,
                    MemStack::new(&mut buf),
                    Spec::default(),
                )
                .unwrap();
                x.copy_from(&rhs);
                let lr = faer::MatRef::from_column_major_slice(l.as_slice(), n, n);
                let xr = faer::MatMut::from_column_major_slice_mut(x.as_mut_slice(), n, 1);
                llt::solve::solve_in_place(lr, xr, Par::Seq, MemStack::new(&mut buf));
            })
        });
        let mut store = Some(a.clone());
        g.bench_with_input(
            BenchmarkId::new("nalgebra_cholesky_reused", n),
            &n,
            |bch, _| {
                bch.iter(|| {
                    let mut m = store.take().unwrap();
                    m.copy_from(&a);
                    let ch = nalgebra::Cholesky::new(m).unwrap();
                    x.copy_from(&rhs);
                    ch.solve_mut(&mut x);
                    store = Some(ch.unpack_dirty());
                })
            },
        );
        g.bench_with_input(
            BenchmarkId::new("nalgebra_lu_allocating", n),
            &n,
            |bch, _| {
                bch.iter(|| {
                    let f = a.clone().lu();
                    x.copy_from(&rhs);
                    f.solve_mut(&mut x);
                })
            },
        );
    }
    g.finish();
}

/// An SPD arrow matrix: a dense root block coupled to `branches` dense blocks that do not
/// couple with each other (a vehicle in relative coordinates: chassis and corners).
fn arrow(root: usize, branches: usize, size: usize) -> DMatrix<f64> {
    let n = root + branches * size;
    DMatrix::from_fn(n, n, |i, j| {
        let coupled = i < root || j < root || (i - root) / size == (j - root) / size;
        let v = if coupled {
            ((i * 7 + j * 7 + i * j) as f64 * 0.37).sin() / n as f64
        } else {
            0.0
        };
        v + if i == j { 2.0 } else { 0.0 }
    })
}

/// Structured against dense Cholesky (factorise + solve) on arrow matrices: the
/// 12-flexible-body vehicle's shape in relative coordinates (6 + 4 × 28 = 118), the rigid
/// vehicle's (6 + 4 × 9 = 42), and denser ones (a larger root) to find where the fill of
/// the sparse factor stops paying (`sparse_llt::MAX_FILL`); the arrow form
/// (`arrow_llt::ArrowLlt`) where it is found.
fn structured(c: &mut Criterion) {
    let mut g = c.benchmark_group("structured_against_dense");
    for (root, branches, size) in [
        (6, 4, 4),
        (6, 4, 9),
        (6, 4, 28),
        (6, 8, 28),
        (30, 4, 22),
        (48, 2, 35),
    ] {
        let a = arrow(root, branches, size);
        let n = a.nrows();
        let rhs = DVector::from_fn(n, |i, _| (i as f64).cos());
        let mut x = rhs.clone();
        let mut sparse = SparseLlt::new(&a).unwrap();
        let fill = sparse.factor_entries() as f64 / (n * (n + 1) / 2) as f64;
        let label = format!("{root}+{branches}x{size} fill {fill:.2}");
        g.bench_with_input(BenchmarkId::new("sparse_llt", &label), &n, |bch, _| {
            bch.iter(|| {
                sparse.factor(&a).unwrap();
                x.copy_from(&rhs);
                sparse.solve_in_place(&mut x);
            })
        });
        if let Some(mut arrow) = ArrowLlt::detect(&a) {
            g.bench_with_input(BenchmarkId::new("arrow_llt", &label), &n, |bch, _| {
                bch.iter(|| {
                    arrow.factor(&a).unwrap();
                    x.copy_from(&rhs);
                    arrow.solve_in_place(&mut x);
                })
            });
        }
        let mut dense = DenseLlt::new(n);
        g.bench_with_input(BenchmarkId::new("dense_llt", &label), &n, |bch, _| {
            bch.iter(|| {
                dense.factor(&a).unwrap();
                x.copy_from(&rhs);
                dense.solve_in_place(&mut x);
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_millis(400)).warm_up_time(std::time::Duration::from_millis(200));
    targets = dense, structured
}
criterion_main!(benches);
