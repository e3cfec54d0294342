//! Static equilibrium under gravity at standstill: sag, journal positions, support forces.
//!
//! In: a scene and its model.
//! Out: a [`Static`]: the sag of every sensor plane's centre [m] (x horizontal, y vertical, up
//! positive, so a sag under gravity is negative), the deflection line at every node [m], and per
//! support the journal centre and support-mass displacement [m], the force of the support on the
//! journal [N] (inertial x, y) and each roller's contact force [N].
//!
//! Method: the time simulation's own static solution (`RollSystem::static_equilibrium`: Newton
//! on the nonlinear contacts from the solution on the linearised supports), at roll angle 0, so
//! the sag is the one a run starts from. The support force on the journal is the rollers'
//! contact forces along their lines of centres, or −K w on a linear support (w: the journal
//! relative to its support mass or the ground).

use nalgebra::{DVector, Vector2};

use crate::dynamics::model::Model;
use crate::dynamics::system::RollSystem;
use crate::scene::{Scene, SupportModel};

/// One support at rest.
#[derive(Debug, Clone, PartialEq)]
pub struct SupportRest {
    /// Named node.
    pub node: String,
    /// Journal centre displacement [m].
    pub journal: Vector2<f64>,
    /// Support mass displacement [m] (zero without one).
    pub stand: Vector2<f64>,
    /// Force of the support on the journal [N].
    pub force: Vector2<f64>,
    /// Contact force per roller [N] with the roller's name (empty on linear supports).
    pub contact: Vec<(String, f64)>,
}

/// The static solution (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Static {
    /// Per sensor: name and centre displacement [m].
    pub sensors: Vec<(String, Vector2<f64>)>,
    /// Node z [m] and displacement [m] along the rotor.
    pub line: Vec<(f64, Vector2<f64>)>,
    /// Per support.
    pub supports: Vec<SupportRest>,
    /// Rotor weight [N].
    pub weight: f64,
}

/// Solves the static equilibrium (module doc).
pub fn solve(scene: &Scene, model: &Model) -> Result<Static, String> {
    let sys = RollSystem::new(scene, model);
    let lin = crate::dynamics::LinearSystem::of_scene(scene, model).map_err(|e| e.to_string())?;
    let q0 = lin
        .k
        .clone()
        .lu()
        .solve(&sys.gravity_at_rest())
        .ok_or("static equilibrium: the linearised supports do not hold every rigid mode")?;
    let q = sys.static_equilibrium(&q0)?;
    let zero = DVector::zeros(sys.n);
    let p = q.rows(0, sys.nm);
    let r = &model.reduced;
    let disp = |node: usize| {
        let rows = r.node_rows(node);
        Vector2::new(
            rows.row(0).dot(&p.transpose()),
            rows.row(1).dot(&p.transpose()),
        )
    };
    let sensors = scene
        .sensors
        .iter()
        .map(|s| (s.clone(), disp(model.rotor.named[s])))
        .collect();
    let line = (0..model.rotor.node_z.len())
        .map(|i| (model.rotor.node_z[i], disp(i)))
        .collect();
    let states = sys.support_states(0.0, &q, &zero);
    let supports = scene
        .supports
        .iter()
        .zip(states)
        .map(|(s, st)| {
            let (force, contact) = match &s.model {
                SupportModel::Rollers(rs) => {
                    let mut f = Vector2::zeros();
                    let mut list = Vec::new();
                    for (ro, fc) in rs.rollers.iter().zip(&st.contact) {
                        f += *fc * Vector2::new(-ro.angle.sin(), ro.angle.cos());
                        list.push((ro.name.clone(), *fc));
                    }
                    (f, list)
                }
                SupportModel::Linear(l) => (
                    -(l.spring_at(0.0).k_matrix() * (st.journal - st.stand)),
                    Vec::new(),
                ),
            };
            SupportRest {
                node: s.node.clone(),
                journal: st.journal,
                stand: st.stand,
                force,
                contact,
            }
        })
        .collect();
    Ok(Static {
        sensors,
        line,
        supports,
        weight: model.rotor.mass() * scene.simulation.gravity,
    })
}
