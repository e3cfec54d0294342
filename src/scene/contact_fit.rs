//! A roller contact's IMPACT law from its geometry: the power law F = k δ^e fitted to the Roark
//! line contact of two cylinders with parallel axes, as the source study did.
//!
//! In: a [`ContactGeometry`] in SI: the journal and roller diameters D₁, D₂ [m], the contact
//! length L [m], Young's modulus [Pa] and Poisson's ratio of each body, and the load range
//! [F_min, F_max] [N] with its number of evenly spaced loads. Out: a [`ContactFit`]: k [N/m^e]
//! and e, and how far the fitted law's penetration lies from the relation it was fitted to
//! (largest relative deviation, the load where it occurs, the load from which on it stays within
//! 1 %).
//!
//! The relation (the source's eqs. 4.4–4.5, which cite Roark's Formulas for Stress and Strain
//! for two cylinders in line contact): with the load per length p = F/L, the compliance
//! C_E = (1−ν₁²)/E₁ + (1−ν₂²)/E₂ and the Hertz half-width of the contact band
//! b = √(2p/π · C_E · D₁D₂/(D₁+D₂)), the approach of the two axes is
//! δ = 2p/π · [(1−ν₁²)/E₁ · (1/3 + ln(2D₁/b)) + (1−ν₂²)/E₂ · (1/3 + ln(2D₂/b))].
//! With one material on both sides this is the source's δ = 2(1−ν²)F/(πLE) · (2/3 + ln(4D₁D₂/b²));
//! with two, each body contributes its own compliance times its own logarithm (the sum of the
//! two cylinders' own flattening, as Roark's cylinder-on-plates case gives it). b is the
//! half-width, as the source states; Roark's tables write b for the full band width, and other
//! line-contact formulas (Johnson; Puttock and Thwaite) differ from this one by a constant in the
//! bracket. This form is kept because it is the source's: with E = 210 GPa, ν = 0.3,
//! Ø115 on Ø125 mm and L = 24.99 mm its fit gives the source's k = 899 590.7 N/mm^e and
//! e = 1.0723 (source 1.0722; `docs/scenes.md`).
//!
//! Method: δ(F) at `points` loads evenly spaced over [F_min, F_max] (the default 20 000 loads over
//! 1–20 000 N are the source's 1 N steps), then least squares of ln F = ln k + e ln δ (a straight
//! line in log space, centred sums). A power law cannot follow the logarithm over many decades of
//! load: over the source's 1–20 000 N its fit lies 11 % from the relation at 1 N and within 1 %
//! from about 200 N on; a range of one to two decades is followed within 1 % throughout.

/// A contact's geometry and materials, in SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactGeometry {
    /// Journal diameter D₁ [m].
    pub journal_diameter: f64,
    /// Roller diameter D₂ [m].
    pub roller_diameter: f64,
    /// Contact length L [m].
    pub length: f64,
    /// The journal's Young's modulus [Pa] and Poisson's ratio.
    pub journal: (f64, f64),
    /// The roller's Young's modulus [Pa] and Poisson's ratio.
    pub roller: (f64, f64),
    /// The fit's smallest and largest load [N].
    pub loads: (f64, f64),
    /// Number of evenly spaced loads the fit uses (≥ 2).
    pub points: usize,
}

/// The power law fitted to a [`ContactGeometry`] and how closely it follows the relation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactFit {
    /// What was fitted.
    pub geometry: ContactGeometry,
    /// k [N/m^e].
    pub k: f64,
    /// Exponent e.
    pub exponent: f64,
    /// Largest relative deviation of the law's penetration (F/k)^(1/e) from the relation's over
    /// the fit's loads.
    pub max_deviation: f64,
    /// The load [N] where that deviation occurs.
    pub max_deviation_load: f64,
    /// The smallest of the fit's loads [N] from which on the deviation stays within 1 %.
    pub within_1pct_from: Option<f64>,
}

impl ContactGeometry {
    /// The Hertz half-width b [m] of the contact band under the load `f` [N].
    pub fn half_width(&self, f: f64) -> f64 {
        let (d1, d2) = (self.journal_diameter, self.roller_diameter);
        let p = f / self.length;
        (2.0 * p / std::f64::consts::PI * self.compliance() * d1 * d2 / (d1 + d2)).sqrt()
    }

    /// The approach δ [m] of the two axes under the load `f` [N] (the module doc's relation).
    pub fn penetration(&self, f: f64) -> f64 {
        let b = self.half_width(f);
        let p = f / self.length;
        let body =
            |d: f64, (e, nu): (f64, f64)| (1.0 - nu * nu) / e * (1.0 / 3.0 + (2.0 * d / b).ln());
        2.0 * p / std::f64::consts::PI
            * (body(self.journal_diameter, self.journal) + body(self.roller_diameter, self.roller))
    }

    /// C_E = (1−ν₁²)/E₁ + (1−ν₂²)/E₂ [1/Pa].
    fn compliance(&self) -> f64 {
        let c = |(e, nu): (f64, f64)| (1.0 - nu * nu) / e;
        c(self.journal) + c(self.roller)
    }

    /// The fit's loads [N], evenly spaced over [`loads`](Self::loads), both ends included.
    fn sample_loads(&self) -> impl Iterator<Item = f64> + '_ {
        let (lo, hi) = self.loads;
        let n = self.points.max(2);
        (0..n).map(move |i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
    }

    /// The power law fitted to this geometry (module doc).
    pub fn fit(&self) -> ContactFit {
        let samples: Vec<(f64, f64)> = self
            .sample_loads()
            .map(|f| (self.penetration(f).ln(), f.ln()))
            .collect();
        let n = samples.len() as f64;
        let mx = samples.iter().map(|s| s.0).sum::<f64>() / n;
        let my = samples.iter().map(|s| s.1).sum::<f64>() / n;
        let sxy: f64 = samples.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
        let sxx: f64 = samples.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
        let exponent = sxy / sxx;
        let k = (my - exponent * mx).exp();
        let mut fit = ContactFit {
            geometry: *self,
            k,
            exponent,
            max_deviation: 0.0,
            max_deviation_load: self.loads.0,
            within_1pct_from: None,
        };
        let mut last_over_1pct = None;
        let loads: Vec<f64> = self.sample_loads().collect();
        for (i, f) in loads.iter().enumerate() {
            let dev = fit.deviation(*f);
            if dev > fit.max_deviation {
                fit.max_deviation = dev;
                fit.max_deviation_load = *f;
            }
            if dev > 0.01 {
                last_over_1pct = Some(i);
            }
        }
        fit.within_1pct_from = match last_over_1pct {
            None => Some(loads[0]),
            Some(i) => loads.get(i + 1).copied(),
        };
        fit
    }
}

impl ContactFit {
    /// The fitted law's penetration [m] under the load `f` [N].
    pub fn law_penetration(&self, f: f64) -> f64 {
        (f / self.k).powf(1.0 / self.exponent)
    }

    /// |law / relation − 1| of the penetration under the load `f` [N].
    pub fn deviation(&self, f: f64) -> f64 {
        (self.law_penetration(f) / self.geometry.penetration(f) - 1.0).abs()
    }

    /// k in N/mm^e (penetration in mm), as scenes write it.
    pub fn k_n_per_mm_e(&self) -> f64 {
        self.k / 1000f64.powf(self.exponent)
    }
}
