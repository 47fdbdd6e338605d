//! One ANCF cable element: Hermite shape functions, constant mass, distributed load,
//! and the elastic energy, force and analytic tangent (docs/methods.md §7.1–§7.2; elastic
//! line approach after Berzeri & Shabana 2000 and Gerstmayr & Shabana 2006, with the
//! corrections of Gerstmayr & Irschik 2008 as methods.md records them).
//!
//! Element coordinates q_e = [r₁; r₁′; r₂; r₂′] (4d values, d = 2 or 3), x ∈ [0, L_e]
//! local to the element, r(x) = Σᵢ Sᵢ(x) q_e,i with
//!
//! S₁ = 1 − 3ξ² + 2ξ³, S₂ = L(ξ − 2ξ² + ξ³), S₃ = 3ξ² − 2ξ³, S₄ = L(−ξ² + ξ³), ξ = x/L.
//!
//! Mass M_e = ρA L/420 [156 22L 54 −13L; 22L 4L² 13L −3L²; 54 13L 156 −22L;
//! −13L −3L² −22L 4L²] ⊗ I; a load p per unit length gives
//! Q_p = L [p/2; L p/12; p/2; −L p/12].
//!
//! Elastic energy U_e = ½ ∫ (EA ε² + EI |κ|²) dx with ε = |r′| − 1 and the material
//! curvature measure |κ|² = |r′ × r″|² / |r′|⁴ (the |r′|² variant of §7.2, which
//! reproduces the Exudyn static check; 2D: κ = (r′ × r″)·e₃ / |r′|²).
//!
//! Both parts are written through the invariants g = r′·r′, p = r″·r″, s = r′·r″,
//! because |r′ × r″|² = g p − s² (Lagrange's identity) in 2D and 3D alike:
//!
//! e_ax = ½ EA (√g − 1)²,  e_b = ½ EI (p/g − s²/g²).
//!
//! Gradient and Hessian with respect to (r′, r″) follow by the chain rule through
//! (g, p, s) (∂g/∂r′ = 2r′, ∂p/∂r″ = 2r″, ∂s/∂r′ = r″, ∂s/∂r″ = r′), and are mapped
//! to q_e by S′ and S″. The tangent is therefore **analytic** (no finite
//! differences); the tests check it against finite differences of the force.
//!
//! Quadrature (§7.2, checked): Gauss order 9 for the axial part and order 5 for
//! bending, i.e. **5 and 3 Gauss points** per element.

/// Largest element size: 4 shape functions × 3 components.
pub(crate) const NE: usize = 12;

/// Shape-function derivatives at one quadrature point, weight already scaled by L_e/2.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GaussPoint {
    pub w: f64,
    /// S′ᵢ(x) (i = 0..4).
    pub d1: [f64; 4],
    /// S″ᵢ(x).
    pub d2: [f64; 4],
}

/// Gauss–Legendre abscissae and weights on [−1, 1].
fn gauss_rule(points: usize) -> (&'static [f64], &'static [f64]) {
    const X3: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
    const W3: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    const X5: [f64; 5] = [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ];
    const W5: [f64; 5] = [
        0.236_926_885_056_189_1,
        0.478_628_670_499_366_5,
        0.568_888_888_888_888_9,
        0.478_628_670_499_366_5,
        0.236_926_885_056_189_1,
    ];
    match points {
        3 => (&X3, &W3),
        5 => (&X5, &W5),
        _ => unreachable!("only the 3- and 5-point rules are used"),
    }
}

/// S(x) of one element of length `l` (docs/methods.md §7.1).
#[cfg(test)]
pub(crate) fn shape(l: f64, x: f64) -> [f64; 4] {
    let xi = x / l;
    [
        1.0 - 3.0 * xi * xi + 2.0 * xi.powi(3),
        l * (xi - 2.0 * xi * xi + xi.powi(3)),
        3.0 * xi * xi - 2.0 * xi.powi(3),
        l * (-xi * xi + xi.powi(3)),
    ]
}

/// S′(x) and S″(x).
pub(crate) fn shape_derivatives(l: f64, x: f64) -> ([f64; 4], [f64; 4]) {
    let (l2, l3) = (l * l, l * l * l);
    (
        [
            -6.0 * x / l2 + 6.0 * x * x / l3,
            1.0 - 4.0 * x / l + 3.0 * x * x / l2,
            6.0 * x / l2 - 6.0 * x * x / l3,
            -2.0 * x / l + 3.0 * x * x / l2,
        ],
        [
            -6.0 / l2 + 12.0 * x / l3,
            -4.0 / l + 6.0 * x / l2,
            6.0 / l2 - 12.0 * x / l3,
            -2.0 / l + 6.0 * x / l2,
        ],
    )
}

/// The quadrature points of an element of length `l` with `points` Gauss points.
pub(crate) fn gauss_points(l: f64, points: usize) -> Vec<GaussPoint> {
    let (xs, ws) = gauss_rule(points);
    xs.iter()
        .zip(ws)
        .map(|(&xi, &w)| {
            let x = 0.5 * l * (xi + 1.0);
            let (d1, d2) = shape_derivatives(l, x);
            GaussPoint {
                w: 0.5 * l * w,
                d1,
                d2,
            }
        })
        .collect()
}

/// The 4 × 4 scalar mass matrix ρA L/420 [...] (multiply by I_d).
pub(crate) fn mass_scalar(rho_a: f64, l: f64) -> [[f64; 4]; 4] {
    let c = rho_a * l / 420.0;
    let (l1, l2) = (l, l * l);
    [
        [156.0 * c, 22.0 * l1 * c, 54.0 * c, -13.0 * l1 * c],
        [22.0 * l1 * c, 4.0 * l2 * c, 13.0 * l1 * c, -3.0 * l2 * c],
        [54.0 * c, 13.0 * l1 * c, 156.0 * c, -22.0 * l1 * c],
        [-13.0 * l1 * c, -3.0 * l2 * c, -22.0 * l1 * c, 4.0 * l2 * c],
    ]
}

/// The scalar weights of a uniform load: Q_p = [L/2, L²/12, L/2, −L²/12] ⊗ p.
pub(crate) fn load_scalar(l: f64) -> [f64; 4] {
    [0.5 * l, l * l / 12.0, 0.5 * l, -l * l / 12.0]
}

/// Section stiffness and quadrature of the (uniform) elements.
#[derive(Clone, Debug)]
pub(crate) struct ElementRule {
    pub d: usize,
    pub ea: f64,
    pub ei: f64,
    pub axial: Vec<GaussPoint>,
    pub bending: Vec<GaussPoint>,
}

impl ElementRule {
    /// Elastic energy of one element; adds ∂U_e/∂q_e into `grad` and, when given,
    /// ∂²U_e/∂q_e² into `hess` (first 4d entries / rows used).
    pub fn energy(
        &self,
        qe: &[f64],
        grad: Option<&mut [f64; NE]>,
        hess: Option<&mut [[f64; NE]; NE]>,
    ) -> f64 {
        let d = self.d;
        let mut grad = grad;
        let mut hess = hess;
        let mut u = 0.0;
        let at = |s: &[f64; 4], k: usize| -> f64 { (0..4).map(|i| s[i] * qe[i * d + k]).sum() };

        // Axial part: e = ½ EA (|a| − 1)², a = r′.
        for gp in &self.axial {
            let mut a = [0.0; 3];
            for k in 0..d {
                a[k] = at(&gp.d1, k);
            }
            let g: f64 = a.iter().map(|v| v * v).sum();
            let na = g.sqrt();
            u += gp.w * 0.5 * self.ea * (na - 1.0).powi(2);
            let c1 = self.ea * (1.0 - 1.0 / na);
            if let Some(gr) = grad.as_deref_mut() {
                for i in 0..4 {
                    for k in 0..d {
                        gr[i * d + k] += gp.w * gp.d1[i] * c1 * a[k];
                    }
                }
            }
            if let Some(h) = hess.as_deref_mut() {
                // H_aa = EA[(1 − 1/|a|) I + a aᵀ/|a|³]
                let c2 = self.ea / (na * na * na);
                let mut haa = [[0.0; 3]; 3];
                for k in 0..d {
                    for l in 0..d {
                        haa[k][l] = c2 * a[k] * a[l] + if k == l { c1 } else { 0.0 };
                    }
                }
                for i in 0..4 {
                    for j in 0..4 {
                        let s = gp.w * gp.d1[i] * gp.d1[j];
                        for k in 0..d {
                            for l in 0..d {
                                h[i * d + k][j * d + l] += s * haa[k][l];
                            }
                        }
                    }
                }
            }
        }

        // Bending part: e = ½ EI f, f = p/g − s²/g².
        let c = 0.5 * self.ei;
        for gp in &self.bending {
            let (mut a, mut b) = ([0.0; 3], [0.0; 3]);
            for k in 0..d {
                a[k] = at(&gp.d1, k);
                b[k] = at(&gp.d2, k);
            }
            let g: f64 = a.iter().map(|v| v * v).sum();
            let p: f64 = b.iter().map(|v| v * v).sum();
            let s: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            let (g2, g3) = (g * g, g * g * g);
            u += gp.w * c * (p / g - s * s / g2);
            let f_g = -p / g2 + 2.0 * s * s / g3;
            let f_p = 1.0 / g;
            let f_s = -2.0 * s / g2;
            if let Some(gr) = grad.as_deref_mut() {
                for k in 0..d {
                    let fa = 2.0 * f_g * a[k] + f_s * b[k];
                    let fb = 2.0 * f_p * b[k] + f_s * a[k];
                    for i in 0..4 {
                        gr[i * d + k] += gp.w * c * (gp.d1[i] * fa + gp.d2[i] * fb);
                    }
                }
            }
            if let Some(h) = hess.as_deref_mut() {
                let f_gg = 2.0 * p / g3 - 6.0 * s * s / (g2 * g2);
                let f_gp = -1.0 / g2;
                let f_gs = 4.0 * s / g3;
                let f_ss = -2.0 / g2;
                // Second derivatives of f in the invariants u = (g, p, s).
                let ff = [[f_gg, f_gp, f_gs], [f_gp, 0.0, 0.0], [f_gs, 0.0, f_ss]];
                // ∂u/∂a and ∂u/∂b, one row per invariant.
                let mut ua = [[0.0; 3]; 3];
                let mut ub = [[0.0; 3]; 3];
                for k in 0..d {
                    ua[0][k] = 2.0 * a[k];
                    ua[2][k] = b[k];
                    ub[1][k] = 2.0 * b[k];
                    ub[2][k] = a[k];
                }
                let mut haa = [[0.0; 3]; 3];
                let mut hab = [[0.0; 3]; 3];
                let mut hbb = [[0.0; 3]; 3];
                for k in 0..d {
                    for l in 0..d {
                        let (mut xaa, mut xab, mut xbb) = (0.0, 0.0, 0.0);
                        for m in 0..3 {
                            for n in 0..3 {
                                xaa += ff[m][n] * ua[m][k] * ua[n][l];
                                xab += ff[m][n] * ua[m][k] * ub[n][l];
                                xbb += ff[m][n] * ub[m][k] * ub[n][l];
                            }
                        }
                        if k == l {
                            xaa += 2.0 * f_g;
                            xbb += 2.0 * f_p;
                            xab += f_s;
                        }
                        haa[k][l] = c * xaa;
                        hab[k][l] = c * xab;
                        hbb[k][l] = c * xbb;
                    }
                }
                for i in 0..4 {
                    for j in 0..4 {
                        let w = gp.w;
                        let (s11, s12, s21, s22) = (
                            w * gp.d1[i] * gp.d1[j],
                            w * gp.d1[i] * gp.d2[j],
                            w * gp.d2[i] * gp.d1[j],
                            w * gp.d2[i] * gp.d2[j],
                        );
                        for k in 0..d {
                            for l in 0..d {
                                h[i * d + k][j * d + l] += s11 * haa[k][l]
                                    + s12 * hab[k][l]
                                    + s21 * hab[l][k]
                                    + s22 * hbb[k][l];
                            }
                        }
                    }
                }
            }
        }
        u
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_interpolate_nodes_and_slopes() {
        let l = 0.7;
        let s0 = shape(l, 0.0);
        let s1 = shape(l, l);
        assert!((s0[0] - 1.0).abs() < 1e-15 && s0[1].abs() < 1e-15 && s0[2].abs() < 1e-15);
        assert!((s1[2] - 1.0).abs() < 1e-15 && s1[3].abs() < 1e-15);
        let (d0, _) = shape_derivatives(l, 0.0);
        let (d1, _) = shape_derivatives(l, l);
        assert!((d0[1] - 1.0).abs() < 1e-15 && (d1[3] - 1.0).abs() < 1e-15);
        // Mass matrix = ∫ ρA S Sᵀ by the 5-point rule (degree 6 integrand, exact).
        let m = mass_scalar(2.0, l);
        let (xs, ws) = gauss_rule(5);
        for i in 0..4 {
            for j in 0..4 {
                let num: f64 = xs
                    .iter()
                    .zip(ws)
                    .map(|(&xi, &w)| {
                        let s = shape(l, 0.5 * l * (xi + 1.0));
                        0.5 * l * w * 2.0 * s[i] * s[j]
                    })
                    .sum();
                assert!((num - m[i][j]).abs() < 1e-14, "M[{i}][{j}]");
            }
        }
    }
}
