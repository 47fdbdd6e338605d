//! Integration rules on the parent elements: points (ξ, η, ζ) and weights.
//!
//! - Hexahedra: Gauss–Legendre product rules, n points per direction, exact for
//!   polynomials of degree 2n − 1 in each variable (Zienkiewicz, Taylor & Zhu 2013, §6.8).
//! - Tetrahedra (parent volume 1/6): the 1-point centroid rule (degree 1); the 4-point rule
//!   at L = (a, b, b, b) and permutations, a = (5 + 3√5)/20, b = (5 − √5)/20, weights 1/24
//!   (degree 2; Zienkiewicz, Taylor & Zhu 2013, Table 6.4; Abaqus's and CalculiX's rule for
//!   C3D10); and a collapsed product rule of degree 2n − 3 for higher degrees: the cube
//!   (u, v, w) ∈ [0, 1]³ mapped by ξ = u, η = v (1 − u), ζ = w (1 − u)(1 − v), Jacobian
//!   (1 − u)² (1 − v), Gauss–Legendre in each of u, v, w (Stroud, *Approximate Calculation
//!   of Multiple Integrals*, 1971, §2.7; Duffy, SIAM J. Numer. Anal. 19, 1982): a polynomial
//!   of degree p in ξ, η, ζ becomes one of degree p + 2 in u, so n points integrate
//!   degree 2n − 3 exactly.

/// One integration point: parent coordinates and weight.
pub type Point = ([f64; 3], f64);

/// Gauss–Legendre points and weights on [−1, 1], n = 1…4.
pub fn gauss_legendre(n: usize) -> &'static [(f64, f64)] {
    const G1: [(f64, f64); 1] = [(0.0, 2.0)];
    const G2: [(f64, f64); 2] = [
        (-0.577_350_269_189_625_8, 1.0),
        (0.577_350_269_189_625_8, 1.0),
    ];
    const G3: [(f64, f64); 3] = [
        (-0.774_596_669_241_483_4, 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        (0.774_596_669_241_483_4, 5.0 / 9.0),
    ];
    const G4: [(f64, f64); 4] = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    ];
    match n {
        1 => &G1,
        2 => &G2,
        3 => &G3,
        _ => &G4,
    }
}

/// The n × n × n Gauss product rule on the parent cube (n = 1…4), ξ fastest.
pub fn hex_gauss(n: usize) -> Vec<Point> {
    let g = gauss_legendre(n);
    let mut out = Vec::with_capacity(n * n * n);
    for &(z, wz) in g {
        for &(y, wy) in g {
            for &(x, wx) in g {
                out.push(([x, y, z], wx * wy * wz));
            }
        }
    }
    out
}

/// The 1-point centroid rule on the parent tetrahedron.
pub fn tet_centroid() -> Vec<Point> {
    vec![([0.25; 3], 1.0 / 6.0)]
}

/// The 4-point degree-2 rule on the parent tetrahedron (module docs).
pub fn tet_four_point() -> Vec<Point> {
    let a = (5.0 + 3.0 * 5.0_f64.sqrt()) / 20.0;
    let b = (5.0 - 5.0_f64.sqrt()) / 20.0;
    // Volume coordinates (L0, L1, L2, L3) with a at position k; (ξ, η, ζ) = (L1, L2, L3).
    (0..4)
        .map(|k| {
            let l = [0, 1, 2, 3].map(|i| if i == k { a } else { b });
            ([l[1], l[2], l[3]], 1.0 / 24.0)
        })
        .collect()
}

/// The collapsed n³-point rule on the parent tetrahedron, exact to degree 2n − 3.
pub fn tet_collapsed(n: usize) -> Vec<Point> {
    let g = gauss_legendre(n);
    let mut out = Vec::with_capacity(n * n * n);
    for &(gu, wu) in g {
        let u = 0.5 * (gu + 1.0);
        for &(gv, wv) in g {
            let v = 0.5 * (gv + 1.0);
            for &(gw, ww) in g {
                let w = 0.5 * (gw + 1.0);
                let jac = (1.0 - u) * (1.0 - u) * (1.0 - v) / 8.0;
                out.push((
                    [u, v * (1.0 - u), w * (1.0 - u) * (1.0 - v)],
                    wu * wv * ww * jac,
                ));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ ξ^a η^b ζ^c over the parent tetrahedron = a! b! c! / (a + b + c + 3)!.
    fn tet_monomial(a: u32, b: u32, c: u32) -> f64 {
        let f = |k: u32| (1..=k).map(f64::from).product::<f64>();
        f(a) * f(b) * f(c) / f(a + b + c + 3)
    }

    fn integrate(rule: &[Point], a: u32, b: u32, c: u32) -> f64 {
        rule.iter()
            .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32))
            .sum()
    }

    /// Each rule integrates every monomial up to its degree exactly.
    #[test]
    fn rules_are_exact_to_their_degree() {
        for (rule, degree) in [
            (tet_centroid(), 1),
            (tet_four_point(), 2),
            (tet_collapsed(3), 3),
            (tet_collapsed(4), 5),
        ] {
            for a in 0..=degree {
                for b in 0..=degree - a {
                    for c in 0..=degree - a - b {
                        let got = integrate(&rule, a, b, c);
                        let want = tet_monomial(a, b, c);
                        assert!((got - want).abs() < 1e-15, "{a} {b} {c}: {got} vs {want}");
                    }
                }
            }
        }
        // Hexahedron: ∫ ξ^a over [−1, 1] = 2/(a + 1) for even a.
        for n in 1..=4 {
            let rule = hex_gauss(n);
            for a in (0..2 * n as u32).step_by(2) {
                let got = integrate(&rule, a, 0, 0);
                assert!((got - 8.0 / f64::from(a + 1)).abs() < 1e-14, "n {n} a {a}");
            }
        }
    }
}
