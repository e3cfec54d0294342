//! A solid or shell body's own modes on its scene's supports at standstill: the whole imported
//! model's, not its Craig–Bampton reduction's, to check the reduction against (or to use where
//! the reduction's truncation is too coarse).
//!
//! In: a [`Scene`] whose body is a solid or shell body (`[fe]` with `[fe.rings]`,
//! [`crate::rotor::import::solid`]) and a count. Out: [`Modes`]: the lowest `count` undamped
//! eigenpairs of the body on its linear supports and drive at standstill, λ = ω² [(rad/s)²]
//! ascending, M-normalised vectors over the body's DOFs (the DOF table's order) and then two
//! coordinates (x, y [m]) per support mass in the scene's support order; or a reason naming the
//! scene key at fault ([`Failure::Key`]): a roller support (`supports[i].type`: a stand's contact has no linear
//! stiffness), unequal cross stiffnesses (`supports[i].spring`: the problem would not be
//! symmetric), a scene whose body is not a solid one ([`solid_of`]) (a scene without
//! supports is refused by the scene's own checks); or the solver's error
//! ([`Failure::Solver`]: more modes asked for than the DOFs).
//! Method: K_s = K + Σ_supports Pᵀ k P and M_s = M ⊕ the support masses, P the spring's
//! elongation: the attachment point's u_x, u_y rows (a ring's RBE3 interpolation, a named
//! node's own DOFs) less the support mass's x, y when there is one, k the spring at Ω = 0
//! ([`LinearSupport::spring_at`]); a support mass adds its ground spring on its own
//! coordinates; the drive adds its axial spring on the drive point's u_z row. The lowest pairs by
//! the shift-invert Lanczos solver of `rotorsweep reduce --free`
//! ([`crate::rotor::sparse_reduction::body_modes`], σ = −(2π · 1 Hz)²,
//! [`crate::rotor::sparse_reduction::BODY_SHIFT_HZ`], below the spin mode the supports leave
//! free; the springs added to the body's sparse K by [`crate::numerics::sparse::Sparse::with_added`]), so these are the frequencies of the same linear model `modes` reports
//! `supported_hz` for, before the reduction. Memory and time: those of one sparse factor of
//! K_s − σM_s and the Lanczos basis, as `reduce`.

use nalgebra::Matrix2;

use crate::numerics::lanczos::Modes;
use crate::rotor::import::solid::SolidBody;
use crate::rotor::reduction::ReductionError;
use crate::rotor::sparse_reduction::body_modes;
use crate::scene::{LinearSupport, Scene, SupportModel};

/// Why the supported modes were not computed.
#[derive(Debug)]
pub enum Failure {
    /// A scene key at fault, and the reason.
    Key(String, String),
    /// The solver's (the count above the DOFs, an indefinite K_s − σM_s …).
    Solver(ReductionError),
}

/// The scene's solid or shell body, or the key to blame (`fe.rings`) when it has none.
pub fn solid_of(scene: &Scene) -> Result<&SolidBody, Failure> {
    scene
        .body
        .as_ref()
        .and_then(|b| b.solid.as_deref())
        .ok_or_else(|| {
            Failure::Key(
                "fe.rings".to_string(),
                "the body is not a solid or shell body (no fe.rings): the whole body on the \
                 scene's supports needs one (an axis body's model is reduced dense)"
                    .to_string(),
            )
        })
}

/// The rows (body DOF, coefficient) of `name`'s six motions (u_x … θ_z).
fn rows<'a>(
    solid: &'a SolidBody,
    name: &str,
    key: &str,
) -> Result<&'a [Vec<(usize, f64)>; 6], Failure> {
    solid
        .attachments
        .iter()
        .find(|a| a.name == name)
        .map(|a| &a.rows)
        .ok_or_else(|| {
            Failure::Key(
                key.to_string(),
                format!("`{name}` is not an attachment point of the body"),
            )
        })
}

/// Adds ½ eᵀ k e for the elongations e_a = Σ (row, coefficient) to `out` (k symmetric 2 × 2, or
/// its (0, 0) entry alone for one elongation).
fn spring(out: &mut Vec<(usize, usize, f64)>, e: &[Vec<(usize, f64)>], k: &Matrix2<f64>) {
    for (a, ea) in e.iter().enumerate() {
        for (b, eb) in e.iter().enumerate() {
            for &(i, x) in ea {
                for &(j, y) in eb {
                    out.push((i, j, k[(a, b)] * x * y));
                }
            }
        }
    }
}

/// The lowest `count` modes of the scene's solid body on its supports (module doc).
pub fn supported_modes(scene: &Scene, count: usize) -> Result<Modes, Failure> {
    let solid = solid_of(scene)?;
    let body = &solid.body;
    let n = body.dofs.len();
    let masses = scene.supports.iter().filter(|s| s.has_mass()).count();
    let total = n + 2 * masses;
    let mut k = Vec::new();
    let mut m = Vec::new();
    let mut next = n;
    for (i, s) in scene.supports.iter().enumerate() {
        let key = format!("supports[{i}]");
        let l: &LinearSupport =
            match &s.model {
                SupportModel::Linear(l) => l,
                SupportModel::Rollers(_) => return Err(Failure::Key(
                    format!("{key}.type"),
                    "a roller support has no linear stiffness: the whole body's supported modes \
                     take linear supports"
                        .to_string(),
                )),
            };
        let r = rows(solid, &s.node, &format!("{key}.node"))?;
        let at = l.spring_at(0.0);
        if at.kxy != at.kyx {
            return Err(Failure::Key(
                format!("{key}.spring"),
                format!(
                    "kxy = {:e} and kyx = {:e} differ: the whole body's supported modes need a \
                     symmetric stiffness",
                    at.kxy, at.kyx
                ),
            ));
        }
        let mut e: Vec<Vec<(usize, f64)>> = vec![r[0].clone(), r[1].clone()];
        if let Some((mass, ground)) = &l.mass {
            e[0].push((next, -1.0));
            e[1].push((next + 1, -1.0));
            if ground.kxy != ground.kyx {
                return Err(Failure::Key(
                    format!("{key}.mass"),
                    "the support mass's ground spring has unequal cross stiffnesses".to_string(),
                ));
            }
            let ground_rows = [vec![(next, 1.0)], vec![(next + 1, 1.0)]];
            spring(&mut k, &ground_rows, &ground.k_matrix());
            m.push((next, next, *mass));
            m.push((next + 1, next + 1, *mass));
            next += 2;
        }
        spring(&mut k, &e, &at.k_matrix());
    }
    if let Some(d) = &scene.drive {
        let r = rows(solid, &d.node, "drive.node")?;
        let kd = Matrix2::new(d.axial_stiffness, 0.0, 0.0, 0.0);
        spring(&mut k, std::slice::from_ref(&r[2]), &kd);
    }
    let k = body.stiffness.with_added(total, k);
    let m = body.mass.with_added(total, m);
    body_modes(&k, &m, count).map_err(Failure::Solver)
}
