//! Membrane patch tests (docs/shells.md): the continuum membranes (`shell.membrane = "cst"`
//! and `"fabric"`, with and without no-compression) against the closed forms of homogeneous
//! states, and the report's edge springs on the same uniaxial test as information.
//!
//! The sheet is the `1 m × 1 m` unstructured rectangle (jittered Delaunay, ℓ = 0.1 m; the
//! springs on all three rectangle patterns, ℓ = 2.5 cm). Strains are measured from the node
//! positions: each triangle's deformation gradient `F = D_s D_m⁻¹` and Green strain
//! `E = ½(FᵀF − I)` in the sheet's x, y axes, independently of the elements' kinematics.
//!
//! **Error budget of the exact rows.** A linear triangle represents a constant deformation
//! gradient exactly, and the St Venant–Kirchhoff laws are exact in the Green strain at any
//! strain, so a homogeneous state is the exact discrete solution whatever the strain (no
//! O(ε) geometric error): what is left is the static solve, converged to a residual of
//! [`FORCE_TOL`] = 1e-11 × the nodal force scale (no tolerance relative to the start),
//! amplified into relative strain errors by the condition number of the sheet's stiffness,
//! ~ (L/ℓ)² = 100: 1e-9, and [`EXACT`] = 1e-8 leaves a factor 10 for that estimate
//! (measured: ≤ 1.2e-12; Newton converges quadratically past its tolerance). Engineering strains `ε = λ − 1` differ from Green strains at O(ε):
//! `−ε₂/ε₁ = ν (1 + (1 + ν) ε₁/2 + O(ε²))`, the budget of the one engineering row.
use super::midedge_cases::PATTERNS;
use super::shell_cases::solve_static_with;
use super::Check;
use crate::mesh::generate::{rectangle_pattern, Pattern};
use crate::scenario::wrinkle::DEFAULT_WRINKLE_STRAIN;
use engine::loads::PointForces;
use engine::shell::{self, CstMembrane, FabricMembrane, Orthotropic, ShellMaterial, TriMesh};
use engine::{DofLayout, Model, NewtonOptions, State};
use nalgebra::{Matrix2, Matrix3x2, Rotation3, Unit, Vector2, Vector3};

/// Cell size of the sheet (m).
pub const ELL: f64 = 0.1;
/// Young's modulus (Pa) of the `cst` and springs cases.
pub const E: f64 = 2.8e8;
/// Poisson ratio of the `cst` cases.
pub const NU: f64 = 0.3;
/// Thickness (m) of every case.
pub const H: f64 = 1e-4;
/// The fabric of the fabric cases: the constants of `scenarios/drop-1000m.toml` (a nylon
/// canopy cloth): E₁ = 280 MPa, E₂ = 224 MPa, G₁₂ = 10 MPa, ν₁₂ = 0.2, h = 0.1 mm.
pub const FABRIC: Orthotropic = Orthotropic {
    warp_modulus: 2.8e8,
    weft_modulus: 2.24e8,
    shear_modulus: 1e7,
    poisson_ratio: 0.2,
    thickness: H,
};
/// Cell size of the springs' sheets (m): their free edges carry a boundary layer that
/// shifts the centre's ν by O(ℓ/L) (+3.3 %, +1.6 %, +0.9 % at ℓ = 0.1, 0.05, 0.025 m on the
/// union-jack, small strain), so the information rows use the finer sheet.
pub const SPRINGS_ELL: f64 = 0.025;
/// Green strain of the uniaxial pulls along the pulled axis.
pub const STRAIN: f64 = 0.01;
/// Residual of the static solves, relative to the nodal force scale `S ℓ`.
pub const FORCE_TOL: f64 = 1e-11;
/// Tolerance of the rows that are exact up to the static solve (module doc).
pub const EXACT: f64 = 1e-8;

fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

/// The test sheet: a `1 m × 1 m` rectangle in one pattern, flat in z = 0,
/// centred at the origin.
pub struct Sheet {
    /// Rest positions.
    pub q: Vec<f64>,
    /// Its triangles, edges, areas and boundary.
    pub tri: TriMesh,
    /// The centre node.
    pub centre: usize,
    /// Cell size (m).
    pub ell: f64,
}

impl Sheet {
    /// The sheet meshed in `pattern` with cells of `ell` (m).
    pub fn new(pattern: Pattern, ell: f64) -> Result<Self, String> {
        let m = rectangle_pattern(1.0, 1.0, ell, pattern);
        let centre = m.node_set("center").ok_or("no centre node")?[0];
        Ok(Self {
            q: m.q(),
            tri: m.tri_mesh().map_err(err)?,
            centre,
            ell,
        })
    }

    fn n_nodes(&self) -> usize {
        self.q.len() / 3
    }

    fn node(v: &[f64], i: usize) -> Vector3<f64> {
        Vector3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2])
    }

    /// Green strain `E = ½(FᵀF − I)` (x, y axes) of every triangle at positions `x`.
    pub fn green_strains(&self, x: &[f64]) -> Result<Vec<Matrix2<f64>>, String> {
        let (rest, at) = (&self.q, Self::node);
        self.tri
            .faces
            .iter()
            .map(|&[a, b, c]| {
                let (r1, r2) = (at(rest, b) - at(rest, a), at(rest, c) - at(rest, a));
                let dm = Matrix2::new(r1.x, r2.x, r1.y, r2.y);
                let ds = Matrix3x2::from_columns(&[at(x, b) - at(x, a), at(x, c) - at(x, a)]);
                let f = ds * dm.try_inverse().ok_or("degenerate rest triangle")?;
                Ok(0.5 * (f.transpose() * f - Matrix2::identity()))
            })
            .collect()
    }

    /// Area-weighted mean of `value` over the triangles whose rest centroid lies in the
    /// central `0.5 m × 0.5 m` window (away from the free edges' boundary layer).
    fn window_mean(&self, value: impl Fn(usize) -> f64) -> f64 {
        let (mut sum, mut area) = (0.0, 0.0);
        for (i, f) in self.tri.faces.iter().enumerate() {
            let c = f
                .iter()
                .map(|&k| Self::node(&self.q, k))
                .sum::<Vector3<f64>>()
                / 3.0;
            if c.x.abs() < 0.25 && c.y.abs() < 0.25 {
                sum += self.tri.face_areas[i] * value(i);
                area += self.tri.face_areas[i];
            }
        }
        sum / area
    }
}

/// A membrane law of the tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Membrane {
    /// Constant-strain triangles with [`E`], [`NU`], [`H`].
    Cst,
    /// The [`FABRIC`] with its warp along `warp` (in the sheet's plane), carrying compression.
    Fabric {
        /// Warp direction.
        warp: [f64; 3],
    },
    /// The report's edge springs, `k_s = (√3/2) E h ℓ̄` with [`E`], [`H`].
    Springs,
}

/// A model of the sheet with `membrane` only (no masses: static solves).
fn model_with(sheet: &Sheet, membrane: Membrane) -> Result<Model, String> {
    let mut model = Model::new(DofLayout::new(sheet.n_nodes(), 0));
    let (name, faces, q) = (shell::STRETCH_NAME, &sheet.tri.faces, &sheet.q);
    match membrane {
        Membrane::Cst => {
            model.add_force(CstMembrane::new(name, faces, q, E, NU, H).map_err(err)?);
        }
        Membrane::Fabric { warp } => {
            let f = FabricMembrane::new(name, faces, q, &FABRIC, warp, None).map_err(err)?;
            model.add_force(f);
        }
        Membrane::Springs => {
            let mat = ShellMaterial {
                youngs_modulus: E,
                thickness: H,
                density: 1.0,
            };
            shell::ShellParts::try_new(&sheet.tri, &mat, &model, q)
                .map_err(err)?
                .springs(&mut model);
        }
    }
    Ok(model)
}

/// The sheet under the dead traction `t` (N per rest length) along `axis` (0 = x, 1 = y) on
/// its edge `X_axis = +½`, the opposite edge on rollers (held along `axis`), the centre node
/// held across and every node in the plane: the Green strain of every triangle at static
/// equilibrium. Consistent nodal loads (`t ℓ_s/2` to each end of a boundary segment) are
/// exact for linear triangles, so a homogeneous state balances them exactly.
pub fn uniaxial(
    sheet: &Sheet,
    membrane: Membrane,
    axis: usize,
    t: f64,
) -> Result<Vec<Matrix2<f64>>, String> {
    let mut model = model_with(sheet, membrane)?;
    let n = sheet.n_nodes();
    let on = |i: usize, side: f64| (sheet.q[3 * i + axis] - 0.5 * side).abs() < 1e-9;
    let mut load = vec![[0.0; 3]; n];
    for &[a, b] in &sheet.tri.edges {
        if on(a, 1.0) && on(b, 1.0) {
            let half = 0.5 * t * (Sheet::node(&sheet.q, b) - Sheet::node(&sheet.q, a)).norm();
            load[a][axis] += half;
            load[b][axis] += half;
        }
    }
    for i in 0..n {
        model.fixed[3 * i + 2] = true;
        model.fixed[3 * i + axis] |= on(i, -1.0);
    }
    model.fixed[3 * sheet.centre + 1 - axis] = true;
    model.add_force(PointForces::new(&(0..n).collect::<Vec<_>>(), &load));
    let state = solve(&mut model, sheet.q.clone(), t * sheet.ell)?;
    sheet.green_strains(&state.q)
}

/// Static equilibrium of `model` from `q`, to the residual `FORCE_TOL × force_scale` (N) and
/// nothing relative to the start's residual (the exact rows' budget, module doc).
fn solve(model: &mut Model, q: Vec<f64>, force_scale: f64) -> Result<State, String> {
    let opts = NewtonOptions {
        force_tol_abs: Some(FORCE_TOL * force_scale),
        force_tol_rel: 0.0,
        ..Default::default()
    };
    solve_static_with(model, q, opts)
}

/// Traction (N/m) that gives the Green strain [`STRAIN`] along the pull in a sheet of
/// uniaxial stiffness `yh` (N/m): `T = λ S = √(1 + 2E) Y h E` (the dead load per rest length
/// is the first Piola–Kirchhoff stress `F S`).
fn traction(yh: f64) -> f64 {
    (1.0 + 2.0 * STRAIN).sqrt() * yh * STRAIN
}

/// The value of `values` farthest from `reference`.
fn worst(values: impl Iterator<Item = f64>, reference: f64) -> f64 {
    values
        .max_by(|a, b| (a - reference).abs().total_cmp(&(b - reference).abs()))
        .unwrap_or(f64::NAN)
}

/// One uniaxial pull, judged: the axial Green strain against [`STRAIN`] and the lateral
/// contraction `−E_across/E_along` against `ratio`, each the worst triangle.
struct Pull<'a> {
    name: &'a str,
    label: &'a str,
    axis: usize,
    ratio: f64,
    ratio_source: &'a str,
    strain_source: &'a str,
}

impl Pull<'_> {
    fn rows(&self, strains: &[Matrix2<f64>]) -> [Check; 2] {
        let (a, b) = (self.axis, 1 - self.axis);
        let n = strains.len();
        [
            Check::new(
                self.name,
                &format!("axial Green strain, {}, worst of {n} triangles", self.label),
                STRAIN,
                self.strain_source,
                worst(strains.iter().map(|e| e[(a, a)]), STRAIN),
                EXACT,
            ),
            Check::new(
                self.name,
                &format!("−E_lat/E_axial, {}, worst of {n} triangles", self.label),
                self.ratio,
                self.ratio_source,
                worst(strains.iter().map(|e| -e[(b, b)] / e[(a, a)]), self.ratio),
                EXACT,
            ),
        ]
    }
}

/// `patch-cst-uniform-stretch`: the displacement patch test (Irons; MacNeal & Harder 1985's
/// membrane patch). The boundary nodes of the unstructured sheet are placed on `x = R F X`
/// (F a 3 % stretch with shear, R a rotation out of the plane), the interior nodes start
/// 0.1 ℓ off it and are solved for: they must land on the map and every triangle must carry
/// the stress `S = Q E(F)` (rotated from its own frame into x, y). Exact: [`EXACT`].
pub fn uniform_stretch_case(_quick: bool) -> Result<Vec<Check>, String> {
    let sheet = Sheet::new(Pattern::Unstructured, ELL)?;
    let f = Matrix2::new(1.03, 0.02, 0.0, 1.01);
    let axis = Unit::new_normalize(Vector3::new(1.0, 2.0, 2.0));
    let rot = Rotation3::from_axis_angle(&axis, 0.7);
    let map = |x: Vector3<f64>| {
        let y = f * Vector2::new(x.x, x.y);
        rot * Vector3::new(y.x, y.y, 0.0)
    };
    let cst =
        CstMembrane::new(shell::STRETCH_NAME, &sheet.tri.faces, &sheet.q, E, NU, H).map_err(err)?;
    let mut model = Model::new(DofLayout::new(sheet.n_nodes(), 0));
    model.add_force(cst.clone());
    let mut q = Vec::with_capacity(sheet.q.len());
    for i in 0..sheet.n_nodes() {
        let mut x = map(Sheet::node(&sheet.q, i));
        if sheet.tri.boundary_nodes.contains(&i) {
            model.fix_node(i);
        } else {
            // A fixed, scattered in-plane offset of 0.1 ℓ: the solve has work to do.
            let k = i as f64;
            x += rot * Vector3::new((1.7 * k).sin(), (2.3 * k).cos(), 0.0) * (0.1 * sheet.ell);
        }
        q.extend(x.iter());
    }
    let green = 0.5 * (f.transpose() * f - Matrix2::identity());
    let s_ref = isotropic_stress(&green);
    let scale = s_ref.abs().max() * sheet.ell;
    let state = solve(&mut model, q, scale)?;
    let off = (0..sheet.n_nodes())
        .map(|i| (Sheet::node(&state.q, i) - map(Sheet::node(&sheet.q, i))).norm())
        .fold(0.0, f64::max);
    let stresses: Vec<Matrix2<f64>> = (0..sheet.tri.faces.len())
        .map(|i| element_to_sheet(&sheet, i, cst.stress(&state.q, i)))
        .collect();
    let name = "patch-cst-uniform-stretch";
    let src = "S = Q E(F), Q = E h/(1 − ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1 − ν)/2]]";
    let n = stresses.len();
    let mut out = vec![Check::near_zero(
        name,
        "largest |x − R F X| / ℓ over the nodes",
        "homogeneous deformation: x = R F X exactly",
        off / sheet.ell,
        EXACT,
    )];
    for (k, (i, j)) in ["S₁₁", "S₂₂", "S₁₂"].iter().zip([(0, 0), (1, 1), (0, 1)]) {
        out.push(Check::new(
            name,
            &format!("{k} (N/m), F = [[1.03, 0.02], [0, 1.01]], worst of {n} triangles"),
            s_ref[(i, j)],
            src,
            worst(stresses.iter().map(|s| s[(i, j)]), s_ref[(i, j)]),
            EXACT,
        ));
    }
    Ok(out)
}

/// The isotropic plane-stress St Venant–Kirchhoff stress `S` (N/m) of [`E`], [`NU`], [`H`]
/// at the Green strain `g`, written out from the law (not the element's code).
fn isotropic_stress(g: &Matrix2<f64>) -> Matrix2<f64> {
    let c = E * H / (1.0 - NU * NU);
    let tr = g.trace();
    c * ((1.0 - NU) * g + NU * tr * Matrix2::identity())
}

/// The Voigt stress `(S₁₁, S₂₂, S₁₂)` of a `cst` triangle `i`, given in its frame (first
/// axis along its first edge, second `n̂ × t₁`), as a tensor in the sheet's x, y axes.
fn element_to_sheet(sheet: &Sheet, i: usize, s: [f64; 3]) -> Matrix2<f64> {
    let [a, b, c] = sheet.tri.faces[i];
    let at = |k| Sheet::node(&sheet.q, k);
    let t1 = (at(b) - at(a)).normalize();
    let n = (at(b) - at(a)).cross(&(at(c) - at(a))).z.signum();
    // Columns t₁ and t₂ = n̂ × t₁ (n̂ = ±ẑ).
    let r = Matrix2::new(t1.x, -n * t1.y, t1.y, n * t1.x);
    r * Matrix2::new(s[0], s[2], s[2], s[1]) * r.transpose()
}

/// `patch-cst-uniaxial-nu`: the unstructured sheet pulled along x and along y to a Green
/// strain of 1 %: exact (`E_lat = −ν E_axial`, `S = Y h E`): [`EXACT`]. The engineering
/// ratio `−ε₂/ε₁` (ε = λ − 1) of the x pull against the same ν: its deviation is
/// `(1 + ν) ε₁/2` = 6.5e-3 at leading order, O(ε₁²) ≈ 1e-4 after it: tolerance ε₁ = 1e-2.
pub fn cst_uniaxial_case(_quick: bool) -> Result<Vec<Check>, String> {
    let sheet = Sheet::new(Pattern::Unstructured, ELL)?;
    let name = "patch-cst-uniaxial-nu";
    let mut out = Vec::new();
    for (axis, label) in [(0, "pull x"), (1, "pull y")] {
        let strains = uniaxial(&sheet, Membrane::Cst, axis, traction(E * H))?;
        let pull = Pull {
            name,
            label,
            axis,
            ratio: NU,
            ratio_source: "SVK uniaxial stress: E₂₂ = −ν E₁₁, ν = 0.3",
            strain_source: "SVK uniaxial stress: T = λ₁ E h E₁₁",
        };
        out.extend(pull.rows(&strains));
        if axis == 0 {
            let eng = |g: f64| (1.0 + 2.0 * g).sqrt() - 1.0;
            out.push(Check::new(
                name,
                "−ε_lat/ε_axial (engineering, ε = λ − 1), pull x, worst triangle",
                NU,
                "ν, to O(ε): −ε₂/ε₁ = ν (1 + (1 + ν) ε₁/2)",
                worst(strains.iter().map(|g| -eng(g[(1, 1)]) / eng(g[(0, 0)])), NU),
                STRAIN,
            ));
        }
    }
    Ok(out)
}

/// `patch-fabric-uniaxial-nu12` (`pull_warp`) and `-nu21`: the fabric sheet with its warp
/// along x and along y, pulled along the warp (contracts by ν₁₂, stiffness E₁ h) or the
/// weft (ν₂₁ = ν₁₂ E₂/E₁, E₂ h): exact, [`EXACT`].
fn fabric_uniaxial(pull_warp: bool) -> Result<Vec<Check>, String> {
    let sheet = Sheet::new(Pattern::Unstructured, ELL)?;
    let nu12 = FABRIC.poisson_ratio;
    let (name, ratio, yh, ratio_source, strain_source) = if pull_warp {
        let src = "orthotropic SVK, warp stress: E_weft = −ν₁₂ E_warp, ν₁₂ = 0.2";
        let s = "T = λ E₁ h E_warp";
        (
            "patch-fabric-uniaxial-nu12",
            nu12,
            FABRIC.warp_modulus,
            src,
            s,
        )
    } else {
        let src = "orthotropic SVK, weft stress: E_warp = −ν₂₁ E_weft, ν₂₁ = ν₁₂ E₂/E₁ = 0.16";
        let s = "T = λ E₂ h E_weft";
        let nu21 = nu12 * FABRIC.weft_modulus / FABRIC.warp_modulus;
        (
            "patch-fabric-uniaxial-nu21",
            nu21,
            FABRIC.weft_modulus,
            src,
            s,
        )
    };
    let mut out = Vec::new();
    for (warp_axis, warp) in [(0, [1.0, 0.0, 0.0]), (1, [0.0, 1.0, 0.0])] {
        let axis = if pull_warp { warp_axis } else { 1 - warp_axis };
        let label = format!(
            "warp along {}, pull {}",
            ["x", "y"][warp_axis],
            ["x", "y"][axis]
        );
        let strains = uniaxial(&sheet, Membrane::Fabric { warp }, axis, traction(yh * H))?;
        let pull = Pull {
            name,
            label: &label,
            axis,
            ratio,
            ratio_source,
            strain_source,
        };
        out.extend(pull.rows(&strains));
    }
    Ok(out)
}

/// `patch-fabric-uniaxial-nu12`: the fabric sheet with its warp along x and along y,
/// pulled along the warp: it contracts by ν₁₂ with stiffness E₁ h. Exact: [`EXACT`].
pub fn fabric_nu12_case(_quick: bool) -> Result<Vec<Check>, String> {
    fabric_uniaxial(true)
}

/// `patch-fabric-uniaxial-nu21`: the same sheets pulled along the weft: they contract by
/// ν₂₁ = ν₁₂ E₂/E₁ with stiffness E₂ h. Exact: [`EXACT`].
pub fn fabric_nu21_case(_quick: bool) -> Result<Vec<Check>, String> {
    fabric_uniaxial(false)
}

/// `patch-springs-uniaxial` (information): the report's edge springs on the same x pull,
/// on the three patterns, in the central window (the free edges have a boundary layer).
/// The springs have no ν of their own: on the equilateral and union-jack lattices they give
/// `ν = 1/3` and `(E h)_eff = E h`, `(2/√3) E h` (`ShellMaterial::effective_membrane`),
/// whatever the material's ν; on other meshes what the mesh gives.
pub fn springs_case(_quick: bool) -> Result<Vec<Check>, String> {
    let mut out = Vec::new();
    for (pattern, tag) in PATTERNS {
        let sheet = Sheet::new(pattern, SPRINGS_ELL)?;
        let strains = uniaxial(&sheet, Membrane::Springs, 0, traction(E * H))?;
        let (e11, e22) = (
            sheet.window_mean(|i| strains[i][(0, 0)]),
            sheet.window_mean(|i| strains[i][(1, 1)]),
        );
        out.push(Check::info(
            "patch-springs-uniaxial",
            &format!("−E_lat/E_axial, {tag} ℓ = {SPRINGS_ELL} m, pull x, centre (information)"),
            1.0 / 3.0,
            "springs: 1/3 on equilateral, union-jack, cross lattices (nominal; the mesh's)",
            -e22 / e11,
        ));
        out.push(Check::info(
            "patch-springs-uniaxial",
            &format!("axial Green strain, {tag}, T = λ E h × 1 %, centre (information)"),
            STRAIN,
            "springs: E h on the equilateral lattice, (2/√3) E h on union-jack and cross",
            e11,
        ));
    }
    Ok(out)
}

/// Principal values of a Voigt stress `(S₁₁, S₂₂, S₁₂)`, larger first.
fn principal(s: &[f64; 3]) -> (f64, f64) {
    let mean = 0.5 * (s[0] + s[1]);
    let r = (0.5 * (s[0] - s[1])).hypot(s[2]);
    (mean + r, mean - r)
}

/// Stresses of every triangle of a fabric sheet with warp `warp` and no-compression
/// regularisation `eps_r` (`None`: the elastic law) at the homogeneous stretch `(sx, sy)`.
fn fabric_stresses(
    sheet: &Sheet,
    warp: [f64; 3],
    eps_r: Option<f64>,
    (sx, sy): (f64, f64),
) -> Result<Vec<[f64; 3]>, String> {
    let m =
        FabricMembrane::new("nc", &sheet.tri.faces, &sheet.q, &FABRIC, warp, eps_r).map_err(err)?;
    let x: Vec<f64> = sheet
        .q
        .chunks(3)
        .flat_map(|p| [sx * p[0], sy * p[1], p[2]])
        .collect();
    Ok((0..sheet.tri.faces.len())
        .map(|i| m.stress(&x, i))
        .collect())
}

/// `patch-no-compression`: the fabric without compression (`no_compression = true`, the
/// default wrinkle strain ε_r = 1e-5), stresses evaluated on the deformed unstructured sheet.
///
/// **Slack** (biaxial compression 2 %, 1 %; warp along x and at 53°): the barrier leaves
/// the principal stresses `μ/|E_i|` (μ = ε_r² k_ref, k_ref = (Q₁₁ + Q₂₂)/2; relative
/// correction (ε_r/E)² ~ 1e-6), where the elastic law carries `~k|E|`: both principal stresses,
/// relative to the elastic law's largest, must be within twice `μ/(min|E_i| max|σ_el|)` ≈ 4e-7 of 0.
/// **Wrinkled** (1 % along the warp, −1 % across): uniaxial `S₁₁ = E₁ h E₁₁` with the
/// barrier's excess `μ/E₁₁ + ν₁₂ μ/γ` (γ = −E₂₂ − ν₁₂ E₁₁ the wrinkle strain) and
/// `S₂₂ = μ/γ`: tolerances twice those leading-order values.
pub fn no_compression_case(_quick: bool) -> Result<Vec<Check>, String> {
    let sheet = Sheet::new(Pattern::Unstructured, ELL)?;
    let eps_r = DEFAULT_WRINKLE_STRAIN;
    let k = FABRIC.stiffness();
    let mu = eps_r * eps_r * 0.5 * (k[0][0] + k[1][1]);
    let green = |s: f64| 0.5 * (s * s - 1.0);
    let name = "patch-no-compression";
    let src = "tension field: no compressive stress (barrier residue μ/|E|)";
    let slack = (0.98, 0.99);
    let (mut high, mut low, mut elastic) = (f64::MIN, f64::MAX, 0.0f64);
    for warp in [[1.0, 0.0, 0.0], [0.6, 0.8, 0.0]] {
        for s in fabric_stresses(&sheet, warp, Some(eps_r), slack)? {
            let (s1, s2) = principal(&s);
            (high, low) = (high.max(s1), low.min(s2));
        }
        for s in fabric_stresses(&sheet, warp, None, slack)? {
            let (s1, s2) = principal(&s);
            elastic = elastic.max(s1.abs()).max(s2.abs());
        }
    }
    let budget = 2.0 * mu / (green(slack.1).abs() * elastic);
    let wrinkled = (1.01, 0.99);
    let stresses = fabric_stresses(&sheet, [1.0, 0.0, 0.0], Some(eps_r), wrinkled)?;
    let (e11, e22) = (green(wrinkled.0), green(wrinkled.1));
    let nu12 = FABRIC.poisson_ratio;
    let gamma = -e22 - nu12 * e11;
    let uniaxial = FABRIC.warp_modulus * H * e11;
    let across = stresses.iter().map(|s| s[1].abs().max(s[2].abs()));
    Ok(vec![
        Check::near_zero(
            name,
            "slack (−2 %, −1 %): largest principal stress / elastic max |σ|",
            src,
            high / elastic,
            budget,
        ),
        Check::near_zero(
            name,
            "slack (−2 %, −1 %): smallest principal stress / elastic max |σ|",
            src,
            low / elastic,
            budget,
        ),
        Check::new(
            name,
            "wrinkled (+1 % warp, −1 % weft): S_warp (N/m), worst triangle",
            uniaxial,
            "tension field: uniaxial S₁₁ = E₁ h E₁₁",
            worst(stresses.iter().map(|s| s[0]), uniaxial),
            2.0 * (mu / e11 + nu12 * mu / gamma) / uniaxial,
        ),
        Check::near_zero(
            name,
            "wrinkled: largest |S_weft|, |S₁₂| / S_warp",
            src,
            worst(across, 0.0) / uniaxial,
            2.0 * mu / gamma / uniaxial,
        ),
    ])
}
