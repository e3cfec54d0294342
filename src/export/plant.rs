//! The linear plant of a scene at one speed as a state-space model, to HDF5, `.npz` or `.mat`.
//!
//! In: the scene's [`LinearSystem`] (the reduced rotor on its linearised supports, stationary
//! frame) and a spin speed Ω [rad/s]. Out: a [`Plant`] ẋ = A x + B u, y = C x + D u with the
//! state x = (q, q̇) (q: modal coordinates [√kg m], then the support masses' x, y [m]) and
//! named inputs and outputs (docs/export.md):
//! - inputs `<node>/force_x`, `<node>/force_y` [N]: a force in the inertial x (horizontal) or
//!   y (vertical) direction at every named node of the rotor; `unbalance/cos`,
//!   `unbalance/sin` [(rad/s)²]: the scene's own unbalance turning with the roll,
//!   f = f_c u_cos + Ŝ f_c u_sin, so u_cos = Ω² cos Ωt, u_sin = Ω² sin Ωt is the unbalance
//!   load of the spinning roll (the steady response is then `linear`'s unbalance response:
//!   X = Ω² (H_cos(iΩ) − i H_sin(iΩ)));
//! - outputs `<sensor>/displacement_x|y` [m], `<sensor>/velocity_x|y` [m/s],
//!   `<sensor>/acceleration_x|y` [m/s²] of the section centre at each sensor (acceleration
//!   has a direct term D).
//!
//! Method: M q̈ + (C(Ω) + Ω G_s) q̇ + K(Ω) q = F u, so A = [[0, I], [−M⁻¹K, −M⁻¹C]],
//! B = [[0], [M⁻¹F]]; M⁻¹ by a dense LU. Files: HDF5 (datasets `A`, `B`, `C`, `D`, row-major,
//! string datasets `inputs`, `outputs`, `states`, attribute `speed_hz`) or `.npz` (the same
//! arrays; numpy's unicode strings for the names) through the `npyz` crate (the `.npy` header
//! and dtypes) in a `zip` container (stored entries), both maintained crates.

use std::io::Write as _;
use std::path::Path;

use nalgebra::{DMatrix, DVector};

use super::mat::{mat_file, Var};
use crate::dynamics::{LinearError, LinearSystem};
use crate::store;

/// A state-space model (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Plant {
    /// State matrix.
    pub a: DMatrix<f64>,
    /// Input matrix.
    pub b: DMatrix<f64>,
    /// Output matrix.
    pub c: DMatrix<f64>,
    /// Direct feed-through.
    pub d: DMatrix<f64>,
    /// Input names.
    pub inputs: Vec<String>,
    /// Output names.
    pub outputs: Vec<String>,
    /// State names.
    pub states: Vec<String>,
    /// The spin speed [Hz].
    pub speed_hz: f64,
}

/// The plant of `sys` at `omega` [rad/s] (module doc).
pub fn plant(sys: &LinearSystem, omega: f64) -> Result<Plant, LinearError> {
    let n = sys.n();
    let nm = sys.nm;
    let (k, c) = sys.at(omega);
    let c = c + omega * &sys.gs;
    let lu = sys.m.clone().lu();
    let solve = |a: &DMatrix<f64>| {
        lu.solve(a)
            .ok_or_else(|| LinearError::Singular("the mass matrix is singular".into()))
    };
    let pad = |v: DVector<f64>| DVector::from_fn(n, |i, _| if i < nm { v[i] } else { 0.0 });
    let mut inputs = Vec::new();
    let mut forces = Vec::new();
    for (name, rows) in &sys.named {
        for (r, dir) in ["x", "y"].iter().enumerate() {
            inputs.push(format!("{name}/force_{dir}"));
            forces.push(pad(rows.row(r).transpose()));
        }
    }
    inputs.push("unbalance/cos".into());
    forces.push(pad(sys.unbalance.clone()));
    inputs.push("unbalance/sin".into());
    forces.push(pad(sys.rotation() * &sys.unbalance));
    let f = DMatrix::from_columns(&forces);
    let ni = f.ncols();
    let mk = solve(&k)?;
    let mc = solve(&c)?;
    let mf = solve(&f)?;
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    a.view_mut((n, 0), (n, n)).copy_from(&(-&mk));
    a.view_mut((n, n), (n, n)).copy_from(&(-&mc));
    let mut b = DMatrix::zeros(2 * n, ni);
    b.view_mut((n, 0), (n, ni)).copy_from(&mf);
    let mut outputs = Vec::new();
    let mut crow: Vec<DVector<f64>> = Vec::new();
    let mut drow: Vec<DVector<f64>> = Vec::new();
    for (name, rows) in &sys.sensors {
        for (r, dir) in ["x", "y"].iter().enumerate() {
            let phi = pad(rows.row(r).transpose());
            let zero = DVector::zeros(n);
            let stack = |p: &DVector<f64>, v: &DVector<f64>| {
                DVector::from_iterator(2 * n, p.iter().chain(v.iter()).copied())
            };
            outputs.push(format!("{name}/displacement_{dir}"));
            crow.push(stack(&phi, &zero));
            drow.push(DVector::zeros(ni));
            outputs.push(format!("{name}/velocity_{dir}"));
            crow.push(stack(&zero, &phi));
            drow.push(DVector::zeros(ni));
            outputs.push(format!("{name}/acceleration_{dir}"));
            crow.push(stack(&-(mk.transpose() * &phi), &-(mc.transpose() * &phi)));
            drow.push(mf.transpose() * &phi);
        }
    }
    let c_out = DMatrix::from_rows(&crow.iter().map(|v| v.transpose()).collect::<Vec<_>>());
    let d_out = DMatrix::from_rows(&drow.iter().map(|v| v.transpose()).collect::<Vec<_>>());
    let mut states: Vec<String> = (0..nm).map(|i| format!("q{i}")).collect();
    states.extend((nm..n).map(|i| format!("support{}_{}", (i - nm) / 2, ["x", "y"][(i - nm) % 2])));
    let rates: Vec<String> = states.iter().map(|s| format!("d{s}/dt")).collect();
    states.extend(rates);
    Ok(Plant {
        a,
        b,
        c: c_out,
        d: d_out,
        inputs,
        outputs,
        states,
        speed_hz: omega / std::f64::consts::TAU,
    })
}

fn row_major(a: &DMatrix<f64>) -> Vec<f64> {
    a.transpose().as_slice().to_vec()
}

impl Plant {
    fn arrays(&self) -> [(&'static str, &DMatrix<f64>); 4] {
        [
            ("A", &self.a),
            ("B", &self.b),
            ("C", &self.c),
            ("D", &self.d),
        ]
    }

    /// Writes the plant as HDF5 (module doc).
    pub fn write_h5(&self, path: &Path) -> hdf5::Result<()> {
        store::write_closed(path, |file| self.fill_h5(file))
    }

    fn fill_h5(&self, file: &hdf5::File) -> hdf5::Result<()> {
        let root = file.group("/")?;
        store::attr_str(
            &root,
            "format",
            "rotorsweep linear plant 1 (docs/export.md)",
        )?;
        store::attr_f64(&root, "speed_hz", self.speed_hz)?;
        store::attr_str(
            &root,
            "model",
            "dx/dt = A x + B u, y = C x + D u; stationary frame; SI units",
        )?;
        for (name, m) in self.arrays() {
            store::dataset_2d(&root, name, m.shape(), &row_major(m), "SI")?;
        }
        store::string_dataset(&root, "inputs", &self.inputs)?;
        store::string_dataset(&root, "outputs", &self.outputs)?;
        store::string_dataset(&root, "states", &self.states)
    }

    /// Writes the plant as a MATLAB Level 5 `.mat` file ([`super::mat`]): `A`, `B`, `C`, `D`
    /// (double), `speed_hz` (1 × 1) and `inputs`, `outputs`, `states` (n × 1 cell arrays of
    /// strings).
    pub fn write_mat(&self, path: &Path) -> std::io::Result<()> {
        let speed = [self.speed_hz];
        let mut vars: Vec<(&str, Var)> = self
            .arrays()
            .into_iter()
            .map(|(name, m)| (name, Var::Matrix(m.nrows(), m.ncols(), m.as_slice())))
            .collect();
        vars.push(("speed_hz", Var::Matrix(1, 1, &speed)));
        vars.push(("inputs", Var::Strings(&self.inputs)));
        vars.push(("outputs", Var::Strings(&self.outputs)));
        vars.push(("states", Var::Strings(&self.states)));
        let text = "MATLAB 5.0 MAT-file, rotorsweep linear plant 1 (docs/export.md): \
                    dx/dt = A x + B u, y = C x + D u; SI";
        std::fs::write(path, mat_file(text, &vars))
    }

    /// Writes the plant as `.npz` (module doc).
    pub fn write_npz(&self, path: &Path) -> std::io::Result<()> {
        use npyz::WriterBuilder;
        let file = std::fs::File::create(path)?;
        let mut zip = zip::ZipWriter::new(file);
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored);
        let err = |e: zip::result::ZipError| std::io::Error::other(e.to_string());
        for (name, m) in self.arrays() {
            let mut buf = Vec::new();
            let shape = [m.nrows() as u64, m.ncols() as u64];
            let mut w = npyz::WriteOptions::new()
                .default_dtype()
                .shape(&shape)
                .writer(&mut buf)
                .begin_nd()?;
            w.extend(row_major(m))?;
            w.finish()?;
            zip.start_file(format!("{name}.npy"), opts).map_err(err)?;
            zip.write_all(&buf)?;
        }
        let speed = [self.speed_hz];
        let mut buf = Vec::new();
        let mut w = npyz::WriteOptions::new()
            .default_dtype()
            .shape(&[])
            .writer(&mut buf)
            .begin_nd()?;
        w.extend(speed)?;
        w.finish()?;
        zip.start_file("speed_hz.npy", opts).map_err(err)?;
        zip.write_all(&buf)?;
        for (name, items) in [
            ("inputs", &self.inputs),
            ("outputs", &self.outputs),
            ("states", &self.states),
        ] {
            let width = items
                .iter()
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(1)
                .max(1);
            let dtype = npyz::DType::Plain(
                format!("<U{width}")
                    .parse::<npyz::TypeStr>()
                    .map_err(|e| std::io::Error::other(e.to_string()))?,
            );
            let mut buf = Vec::new();
            let mut w = npyz::WriteOptions::<String>::new()
                .dtype(dtype)
                .shape(&[items.len() as u64])
                .writer(&mut buf)
                .begin_nd()?;
            w.extend(items.iter().cloned())?;
            w.finish()?;
            zip.start_file(format!("{name}.npy"), opts).map_err(err)?;
            zip.write_all(&buf)?;
        }
        zip.finish().map_err(err)?;
        Ok(())
    }
}
