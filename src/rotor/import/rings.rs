//! Ring attachments of a solid or shell body: a reference point whose motion is the weighted
//! mean of a ring of nodes (an interpolation element like Nastran's RBE3).
//!
//! In: a [`RingSpec`] (the ring's nodes by id, or by position: every node within a tolerance
//! of the circle of radius `radius` about the z axis at axial position `z`, in the body's
//! length unit; optional weights, one per node, default 1) and the body's node table (SI).
//! Out: a [`Ring`]: its node ids (ascending), weights, the reference point c [m] (the weighted
//! centroid) and the 6 × 3k interpolation matrix R that gives the reference point's motion
//! (u_x, u_y, u_z [m], θ_x, θ_y, θ_z [rad]) from the ring nodes' translations (node by node,
//! x y z); or a reason (the caller names the file and key): no node (an empty `nodes` or none
//! on the circle), a node id the table lacks
//! or given twice, weights not positive or not one per node, nodes on a line (the reference's
//! rotations undetermined).
//! Method: the weighted least-squares rigid motion of the ring (the RBE3 definition, MSC
//! Nastran Quick Reference Guide, RBE3): with r_i = x_i − c and S_i = [I, −[r_i]×] (the
//! translation of node i under a rigid motion (u, θ) of the reference), A = Σ w_i S_iᵀ S_i and
//! R = A⁻¹ [w_1 S_1ᵀ … w_k S_kᵀ]. Because c is the weighted centroid, Σ w_i r_i = 0, A is
//! block-diagonal and the reference translation is exactly the weighted mean of the nodes'
//! translations; the rotations are the least-squares fit. A force and moment F on the reference
//! point are distributed to the ring as Rᵀ F (the same virtual work), and a rigid motion of the
//! ring gives the reference exactly that motion. Only the nodes' translations enter (a shell
//! node's rotations do not, as in RBE3's usual use).

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};

use super::tables::Node;

/// A ring as the scene gives it (module doc); lengths in the body's unit.
#[derive(Debug, Clone, PartialEq)]
pub struct RingSpec {
    /// Node ids of the ring, or `None` to select them by position.
    pub nodes: Option<Vec<i64>>,
    /// Axial position of the circle.
    pub z: Option<f64>,
    /// Radius of the circle.
    pub radius: Option<f64>,
    /// Distance from the circle within which a node is on it (default 1e-6 of the radius).
    pub tolerance: Option<f64>,
    /// Weights, one per node in ascending id order (default 1 each).
    pub weights: Option<Vec<f64>>,
}

/// A ring attachment (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Ring {
    /// Node ids, ascending.
    pub nodes: Vec<i64>,
    /// Weight of each node.
    pub weights: Vec<f64>,
    /// Reference point c [m].
    pub centre: [f64; 3],
    /// R: 6 × 3k, the reference motion from the nodes' translations (module doc).
    pub matrix: DMatrix<f64>,
}

fn cross(r: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -r.z, r.y, r.z, 0.0, -r.x, -r.y, r.x, 0.0)
}

/// The nodes of `spec` (module doc), `length` metres per unit of the spec's lengths.
fn select(spec: &RingSpec, table: &[Node], length: f64) -> Result<Vec<i64>, String> {
    if let Some(ids) = &spec.nodes {
        if spec.z.is_some() || spec.radius.is_some() || spec.tolerance.is_some() {
            return Err("give either `nodes` or `z` and `radius`, not both".into());
        }
        if ids.is_empty() {
            return Err("`nodes` is empty: a ring needs three or more nodes not on a line".into());
        }
        let mut ids = ids.clone();
        ids.sort_unstable();
        if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
            return Err(format!("node {} is given twice", w[0]));
        }
        if let Some(id) = ids.iter().find(|id| !table.iter().any(|n| n.id == **id)) {
            return Err(format!("node {id} does not exist in the node table"));
        }
        return Ok(ids);
    }
    let (Some(z), Some(radius)) = (spec.z, spec.radius) else {
        return Err("a ring needs `nodes`, or `z` and `radius`".into());
    };
    if !(radius > 0.0 && radius.is_finite() && z.is_finite()) {
        return Err(format!(
            "z = {z} and radius = {radius}: need finite z and radius > 0"
        ));
    }
    let tol = spec.tolerance.unwrap_or(1e-6 * radius);
    if !(tol > 0.0 && tol.is_finite()) {
        return Err(format!("tolerance = {tol}: must be a positive number"));
    }
    let (z, radius, tol) = (z * length, radius * length, tol * length);
    let mut ids: Vec<i64> = table
        .iter()
        .filter(|n| (n.x[2] - z).abs() <= tol && (n.x[0].hypot(n.x[1]) - radius).abs() <= tol)
        .map(|n| n.id)
        .collect();
    ids.sort_unstable();
    if ids.is_empty() {
        return Err(format!(
            "no node lies within {tol:e} m of the circle of radius {radius} m at z = {z} m"
        ));
    }
    Ok(ids)
}

/// The ring of `spec` on the node table `table` (SI), the spec's lengths in units of
/// `length` metres (module doc).
pub fn ring(spec: &RingSpec, table: &[Node], length: f64) -> Result<Ring, String> {
    let nodes = select(spec, table, length)?;
    let weights = match &spec.weights {
        Some(w) if w.len() != nodes.len() => {
            return Err(format!(
                "{} weights for {} nodes: give one per node",
                w.len(),
                nodes.len()
            ))
        }
        Some(w) => {
            if let Some(x) = w.iter().find(|x| !(**x > 0.0 && x.is_finite())) {
                return Err(format!("weight {x}: weights must be positive numbers"));
            }
            w.clone()
        }
        None => vec![1.0; nodes.len()],
    };
    let x: Vec<Vector3<f64>> = nodes
        .iter()
        .map(|id| {
            let n = table
                .iter()
                .find(|n| n.id == *id)
                .expect("selected from the table");
            Vector3::from(n.x)
        })
        .collect();
    let total: f64 = weights.iter().sum();
    let c = x
        .iter()
        .zip(&weights)
        .fold(Vector3::zeros(), |s, (xi, w)| s + xi * *w)
        / total;
    let s: Vec<nalgebra::SMatrix<f64, 3, 6>> = x
        .iter()
        .map(|xi| {
            let mut si = nalgebra::SMatrix::<f64, 3, 6>::zeros();
            si.fixed_view_mut::<3, 3>(0, 0)
                .copy_from(&Matrix3::identity());
            si.fixed_view_mut::<3, 3>(0, 3)
                .copy_from(&-cross(&(xi - c)));
            si
        })
        .collect();
    let a: Matrix6<f64> = s
        .iter()
        .zip(&weights)
        .fold(Matrix6::zeros(), |acc, (si, w)| {
            acc + si.transpose() * si * *w
        });
    let rot = a.fixed_view::<3, 3>(3, 3).into_owned().symmetric_eigen();
    let (lo, hi) = rot
        .eigenvalues
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(l, h), &e| (l.min(e), h.max(e)));
    if lo.is_nan() || lo <= 1e-10 * hi {
        return Err(format!(
            "the {} nodes lie on a line: the reference point's rotations are undetermined",
            nodes.len()
        ));
    }
    let a_inv = a
        .try_inverse()
        .ok_or("the ring's normal matrix is singular")?;
    let mut matrix = DMatrix::zeros(6, 3 * nodes.len());
    for (i, (si, w)) in s.iter().zip(&weights).enumerate() {
        let block = a_inv * si.transpose() * *w;
        matrix.view_mut((0, 3 * i), (6, 3)).copy_from(&block);
    }
    Ok(Ring {
        nodes,
        weights,
        centre: [c.x, c.y, c.z],
        matrix,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle(k: usize, radius: f64, z: f64) -> Vec<Node> {
        (0..k)
            .map(|i| {
                let a = 2.0 * std::f64::consts::PI * i as f64 / k as f64;
                Node {
                    id: 10 + i as i64,
                    x: [radius * a.cos(), radius * a.sin(), z],
                }
            })
            .collect()
    }

    fn spec(z: f64, radius: f64) -> RingSpec {
        RingSpec {
            nodes: None,
            z: Some(z),
            radius: Some(radius),
            tolerance: None,
            weights: None,
        }
    }

    #[test]
    fn a_rigid_motion_of_the_ring_moves_the_reference_point_alike() {
        // Exact for any rigid motion u_i = u + θ × r_i (module doc: least squares of a motion
        // the ring makes exactly); here with unequal weights.
        let mut table = circle(7, 0.16, 0.5);
        table.push(Node {
            id: 99,
            x: [0.0, 0.0, 0.7],
        });
        let mut sp = spec(500.0, 160.0);
        sp.weights = Some(vec![1.0, 2.0, 0.5, 1.0, 3.0, 1.0, 1.5]);
        let r = ring(&sp, &table, 1e-3).expect("a ring");
        assert_eq!(r.nodes, (10..17).collect::<Vec<_>>());
        let (u, th) = (
            Vector3::new(1e-3, -2e-3, 5e-4),
            Vector3::new(3e-3, 1e-3, -2e-3),
        );
        let c = Vector3::from(r.centre);
        let q: Vec<f64> = table[..7]
            .iter()
            .flat_map(|n| {
                let v = u + th.cross(&(Vector3::from(n.x) - c));
                [v.x, v.y, v.z]
            })
            .collect();
        let out = &r.matrix * nalgebra::DVector::from_vec(q);
        for i in 0..3 {
            assert!((out[i] - u[i]).abs() < 1e-15 && (out[3 + i] - th[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn an_n_lobe_ovalization_does_not_move_the_reference_point() {
        // Radial displacement cos(n α) on k equally spaced nodes sums to 0 for 0 < n < k
        // (the discrete orthogonality of the Fourier modes): the reference point does not move.
        let table = circle(24, 0.3, 1.0);
        let r = ring(&spec(1.0, 0.3), &table, 1.0).expect("a ring");
        for n in [2, 3] {
            let q: Vec<f64> = (0..24)
                .flat_map(|i| {
                    let a = 2.0 * std::f64::consts::PI * i as f64 / 24.0;
                    let w = (n as f64 * a).cos();
                    [w * a.cos(), w * a.sin(), 0.0]
                })
                .collect();
            let out = &r.matrix * nalgebra::DVector::from_vec(q);
            assert!(out.amax() < 1e-15, "n = {n}: {out}");
        }
    }

    #[test]
    fn bad_rings_are_refused_with_their_reason() {
        let table = circle(5, 0.1, 0.0);
        let bad = |s: RingSpec| ring(&s, &table, 1.0).unwrap_err();
        assert!(bad(spec(0.2, 0.1)).contains("no node lies within"));
        let mut s = spec(0.0, 0.1);
        s.weights = Some(vec![1.0; 3]);
        assert!(bad(s).contains("3 weights for 5 nodes"));
        let ids = |v: Vec<i64>| RingSpec {
            nodes: Some(v),
            z: None,
            radius: None,
            tolerance: None,
            weights: None,
        };
        assert!(bad(ids(vec![10, 11, 10])).contains("node 10 is given twice"));
        assert!(bad(ids(vec![10, 77])).contains("node 77 does not exist"));
        assert!(bad(ids(vec![10])).contains("lie on a line"));
    }
}
