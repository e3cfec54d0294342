//! Sampled studies (`[sample]`) and their statistics and Sobol' indices, each against a closed
//! form or a published value: the marginals of Monte Carlo, Latin hypercube and scrambled
//! Sobol' samples (Kolmogorov–Smirnov), a Gaussian copula's correlation (Fisher's z), the
//! Saltelli/Jansen estimators on the Ishigami function (Ishigami & Homma 1990), the shipped
//! rigid-Jeffcott study's indices against their closed form (derived in
//! studies/sensitivity-jeffcott.toml), the mean and standard deviation of a linear output (the
//! static sag, linear in the density) under a normal input with intervals of normal theory's
//! width, a Gaussian copula's rank correlation under uniform and lognormal marginals (Kruskal
//! 1958), identical bytes at 1 and 2 threads, through shards and after kills and resumes, Morris
//! elementary effects of a linear output (Morris 1991; Campolongo et al. 2007), a sampled study
//! on a grid axis (statistics, indices and samples per grid point), and bad `[sample]` tables
//! named by file, key and line.

use crate::support;

use rotorsweep::numerics::rng::SplitMix64;
use rotorsweep::numerics::sobol_indices::sobol_indices;
use rotorsweep::study::run as campaign;
use rotorsweep::study::Study;
use statrs::distribution::{ContinuousCDF, LogNormal, Normal};
use std::f64::consts::PI;
use support::{report_table, results_content, scratch, write_file};

/// A study text on the rigid Jeffcott rotor (studies/scenes/rigid-jeffcott.toml) with `body`.
fn jeffcott_study(body: &str) -> String {
    let scene = support::repo().join("studies/scenes/rigid-jeffcott.toml");
    format!(
        "name = \"sampled\"\nscene = {:?}\n{body}",
        scene.display().to_string()
    )
}

/// The values of `key` over the study's jobs, as numbers.
fn values(st: &Study, key: &str) -> Vec<f64> {
    st.jobs
        .iter()
        .map(|j| st.value_of(j, key).and_then(|v| v.as_float()).unwrap())
        .collect()
}

/// The Kolmogorov–Smirnov distance sup |F_n − F| of a sample against the CDF `cdf`.
fn ks_distance(mut x: Vec<f64>, cdf: impl Fn(f64) -> f64) -> f64 {
    x.sort_by(f64::total_cmp);
    let n = x.len() as f64;
    x.iter()
        .enumerate()
        .map(|(i, v)| {
            let f = cdf(*v);
            (f - i as f64 / n).abs().max(((i + 1) as f64 / n - f).abs())
        })
        .fold(0.0, f64::max)
}

#[test]
fn marginals_pass_kolmogorov_smirnov() {
    let d = scratch("sample-ks");
    let n = 512;
    let normal = Normal::new(7.0, 0.5).unwrap();
    // Lognormal from mean 7850, std 400: σ² = ln(1 + (400/7850)²), μ = ln 7850 − σ²/2.
    let s2 = (1.0 + (400.0f64 / 7850.0).powi(2)).ln();
    let lognormal = LogNormal::new(7850f64.ln() - s2 / 2.0, s2.sqrt()).unwrap();
    let trunc = Normal::new(1e-3, 5e-4).unwrap();
    let (ta, tb) = (trunc.cdf(2e-4), trunc.cdf(2e-3));
    for method in ["monte-carlo", "latin-hypercube", "sobol"] {
        let text = jeffcott_study(&format!(
            "[sample]\nmethod = \"{method}\"\nn = {n}\nseed = 7\n\
             [[sample.parameters]]\nkey = \"speed.hz\"\ndistribution = \"normal\"\nmean = 7.0\nstd = 0.5\n\
             [[sample.parameters]]\nkey = \"materials.steel.density_kg_m3\"\ndistribution = \"lognormal\"\nmean = 7850.0\nstd = 400.0\n\
             [[sample.parameters]]\nkey = \"simulation.t_end_s\"\ndistribution = \"uniform\"\nlower = 0.1\nupper = 0.2\n\
             [[sample.parameters]]\nkey = \"solver.hmax\"\ndistribution = \"truncated-normal\"\nmean = 1e-3\nstd = 5e-4\nlower = 2e-4\nupper = 2e-3\n"
        ));
        let st = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
        assert_eq!(st.jobs.len(), n);
        let distances = [
            ks_distance(values(&st, "speed.hz"), |x| normal.cdf(x)),
            ks_distance(values(&st, "materials.steel.density_kg_m3"), |x| {
                lognormal.cdf(x)
            }),
            ks_distance(values(&st, "simulation.t_end_s"), |x| (x - 0.1) / 0.1),
            ks_distance(values(&st, "solver.hmax"), |x| {
                (trunc.cdf(x) - ta) / (tb - ta)
            }),
        ];
        // The 1 % critical value of the one-sample KS test, 1.63/√n (Massey 1951, Table 1,
        // asymptotic form): independent draws stay below it.
        let critical = 1.63 / (n as f64).sqrt();
        eprintln!(
            "{method}: KS distances {distances:?} (1 % critical {critical}, 1/n {})",
            1.0 / n as f64
        );
        for (k, dn) in distances.iter().enumerate() {
            assert!(
                *dn < critical,
                "{method}, parameter {k}: D = {dn} ≥ {critical}"
            );
        }
        // A Latin hypercube has one point in each of the n equal-probability strata (McKay,
        // Beckman & Conover 1979), and the scrambled Sobol' points of n = 2⁹ are a (0, 9, 1)-net
        // in each coordinate (Owen 1995): both have D ≤ 1/n (up to the Sobol' points' 2⁻²⁴).
        if method != "monte-carlo" {
            for (k, dn) in distances.iter().enumerate() {
                assert!(
                    *dn <= 1.0 / n as f64 + 1e-6,
                    "{method}, parameter {k}: D = {dn}"
                );
            }
        }
    }
}

#[test]
fn gaussian_copula_gives_the_asked_correlation() {
    let d = scratch("sample-copula");
    let n = 2000;
    let text = jeffcott_study(&format!(
        "[sample]\nmethod = \"monte-carlo\"\nn = {n}\nseed = 3\ncorrelation = [[1.0, 0.6], [0.6, 1.0]]\n\
         [[sample.parameters]]\nkey = \"speed.hz\"\ndistribution = \"normal\"\nmean = 7.0\nstd = 0.5\n\
         [[sample.parameters]]\nkey = \"materials.steel.density_kg_m3\"\ndistribution = \"normal\"\nmean = 7850.0\nstd = 300.0\n"
    ));
    let st = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
    let (x, y) = (
        values(&st, "speed.hz"),
        values(&st, "materials.steel.density_kg_m3"),
    );
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (mx, my) = (mean(&x), mean(&y));
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    let syy: f64 = y.iter().map(|b| (b - my).powi(2)).sum();
    let r = sxy / (sxx * syy).sqrt();
    // Normal marginals: the samples' correlation is the copula's 0.6. Fisher's z = atanh r is
    // normal with standard error 1/√(n − 3) (Fisher 1921): within 2.58 of them (99 %).
    let z_err = (r.atanh() - 0.6f64.atanh()).abs() * ((n - 3) as f64).sqrt();
    eprintln!("copula: r = {r} against 0.6 ({z_err} standard errors of Fisher's z)");
    assert!(z_err < 2.58, "r = {r}, {z_err} standard errors from 0.6");
}

/// Ranks 0 … n − 1 of `x` (no ties in continuous samples).
fn ranks(x: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..x.len()).collect();
    order.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
    let mut r = vec![0.0; x.len()];
    for (rank, &i) in order.iter().enumerate() {
        r[i] = rank as f64;
    }
    r
}

/// Pearson's product-moment correlation of two samples.
fn pearson(x: &[f64], y: &[f64]) -> f64 {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (mx, my) = (mean(x), mean(y));
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    let syy: f64 = y.iter().map(|b| (b - my).powi(2)).sum();
    sxy / (sxx * syy).sqrt()
}

/// A Gaussian copula under marginals that are not normal (uniform and lognormal), by every
/// method that takes one: each marginal stays its own (Kolmogorov–Smirnov at 1 %, Massey 1951)
/// and the samples' rank correlation is the copula's, Spearman's ρ_S = (6/π) asin(ρ/2) for a
/// Gaussian copula of correlation ρ (Kruskal 1958; Nelsen 2006, §5.1.2): 0.5819 for ρ = 0.6
/// (a pair of normal marginals would show the product-moment 0.6 itself). Fisher's z of
/// Spearman's ρ has standard error √(1.06/(n − 3)) (Fieller, Hartley & Pearson 1957): within
/// 2.58 of them (99 %).
#[test]
fn gaussian_copula_gives_its_rank_correlation_under_any_marginals() {
    let d = scratch("sample-copula-ranks");
    let n = 2048;
    let rho: f64 = 0.6;
    let spearman = 6.0 / PI * (rho / 2.0).asin();
    let s2 = (1.0 + (800.0f64 / 7850.0).powi(2)).ln();
    let lognormal = LogNormal::new(7850f64.ln() - s2 / 2.0, s2.sqrt()).unwrap();
    for method in ["monte-carlo", "latin-hypercube", "sobol"] {
        let text = jeffcott_study(&format!(
            "[sample]\nmethod = \"{method}\"\nn = {n}\nseed = 11\ncorrelation = [[1.0, {rho}], [{rho}, 1.0]]\n\
             [[sample.parameters]]\nkey = \"speed.hz\"\ndistribution = \"uniform\"\nlower = 5.0\nupper = 9.0\n\
             [[sample.parameters]]\nkey = \"materials.steel.density_kg_m3\"\ndistribution = \"lognormal\"\nmean = 7850.0\nstd = 800.0\n"
        ));
        let st = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
        let (x, y) = (
            values(&st, "speed.hz"),
            values(&st, "materials.steel.density_kg_m3"),
        );
        let critical = 1.63 / (n as f64).sqrt();
        let dx = ks_distance(x.clone(), |v| (v - 5.0) / 4.0);
        let dy = ks_distance(y.clone(), |v| lognormal.cdf(v));
        let r_s = pearson(&ranks(&x), &ranks(&y));
        let z_err = (r_s.atanh() - spearman.atanh()).abs() / (1.06 / (n - 3) as f64).sqrt();
        eprintln!(
            "{method}: KS {dx:.4}, {dy:.4} (1 % critical {critical:.4}); Spearman {r_s:.4} \
             against {spearman:.4} ({z_err:.2} standard errors), product-moment {:.4}",
            pearson(&x, &y)
        );
        assert!(dx < critical && dy < critical, "{method}: D = {dx}, {dy}");
        assert!(
            z_err < 2.58,
            "{method}: ρ_S = {r_s}, {z_err} standard errors"
        );
    }
}

#[test]
fn saltelli_and_jansen_estimators_recover_the_ishigami_indices() {
    // Ishigami & Homma (1990): f = sin x₁ + a sin² x₂ + b x₃⁴ sin x₁, xᵢ ~ U(−π, π), a = 7,
    // b = 0.1. Analytic variances (Sobol' & Levitan 1999): V₁ = bπ⁴/5 + b²π⁸/50 + 1/2,
    // V₂ = a²/8, V₃ = 0, V₁₃ = 8b²π⁸/225, V = V₁ + V₂ + V₁₃.
    let (a, b) = (7.0, 0.1);
    let v1 = b * PI.powi(4) / 5.0 + b * b * PI.powi(8) / 50.0 + 0.5;
    let v2 = a * a / 8.0;
    let v13 = 8.0 * b * b * PI.powi(8) / 225.0;
    let v = v1 + v2 + v13;
    let first = [v1 / v, v2 / v, 0.0];
    let total = [(v1 + v13) / v, v2 / v, v13 / v];
    // The published values (Saltelli et al. 2010, §4): S = 0.3139, 0.4424, 0; S_T = 0.5576,
    // 0.4424, 0.2437.
    for (got, want) in first.iter().zip([0.3139, 0.4424, 0.0]) {
        assert!((got - want).abs() < 1e-4);
    }
    for (got, want) in total.iter().zip([0.5576, 0.4424, 0.2437]) {
        assert!((got - want).abs() < 1e-4);
    }
    let f = |x: &[f64]| x[0].sin() + a * x[1].sin().powi(2) + b * x[2].powi(4) * x[0].sin();
    let n = 20_000;
    let mut rng = SplitMix64::new(11);
    let mut draw = || -> Vec<f64> { (0..3).map(|_| -PI + 2.0 * PI * rng.uniform()).collect() };
    let (pa, pb): (Vec<Vec<f64>>, Vec<Vec<f64>>) = (0..n).map(|_| (draw(), draw())).unzip();
    let fa: Vec<f64> = pa.iter().map(|x| f(x)).collect();
    let fb: Vec<f64> = pb.iter().map(|x| f(x)).collect();
    let fab: Vec<Vec<f64>> = (0..3)
        .map(|i| {
            pa.iter()
                .zip(&pb)
                .map(|(x, y)| {
                    let mut m = x.clone();
                    m[i] = y[i];
                    f(&m)
                })
                .collect()
        })
        .collect();
    let (ix, used) = sobol_indices(&fa, &fb, &fab, 300, 5).unwrap();
    assert_eq!(used, n);
    for i in 0..3 {
        let (s, t) = (ix[i].first_order, ix[i].total);
        eprintln!(
            "Ishigami x{}: S {:.4} [{:.4}, {:.4}] exact {:.4}; S_T {:.4} [{:.4}, {:.4}] exact {:.4}",
            i + 1,
            s.value,
            s.low,
            s.high,
            first[i],
            t.value,
            t.low,
            t.high,
            total[i]
        );
        assert!(
            s.low <= first[i] && first[i] <= s.high,
            "S_{}: {} [{}, {}], exact {}",
            i + 1,
            s.value,
            s.low,
            s.high,
            first[i]
        );
        assert!(
            t.low <= total[i] && total[i] <= t.high,
            "S_T{}: {} [{}, {}], exact {}",
            i + 1,
            t.value,
            t.low,
            t.high,
            total[i]
        );
    }
}

/// The rows of a `report --table NAME --format json` table as (column → value) objects.
fn rows(table: &serde_json::Value) -> Vec<serde_json::Map<String, serde_json::Value>> {
    let cols: Vec<String> = table["columns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_str().unwrap().to_string())
        .collect();
    table["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            cols.iter()
                .cloned()
                .zip(r.as_array().unwrap().iter().cloned())
                .collect()
        })
        .collect()
}

fn num(row: &serde_json::Map<String, serde_json::Value>, col: &str) -> f64 {
    row[col].as_f64().unwrap()
}

#[test]
fn shipped_jeffcott_study_indices_match_their_closed_form() {
    // studies/sensitivity-jeffcott.toml with n = 64 instead of 256 (wider intervals, a quarter
    // of the time); its comments derive the closed forms.
    let d = scratch("sample-jeffcott");
    let text = std::fs::read_to_string(support::repo().join("studies/sensitivity-jeffcott.toml"))
        .unwrap()
        .replace("n = 256", "n = 64")
        .replace(
            "scene = \"scenes/rigid-jeffcott.toml\"",
            &format!(
                "scene = {:?}",
                support::repo()
                    .join("studies/scenes/rigid-jeffcott.toml")
                    .display()
                    .to_string()
            ),
        );
    let st = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
    assert_eq!(st.jobs.len(), 64 * 5);
    let out = d.join("s.h5");
    campaign::run(&st, &support::run_options(&out)).unwrap();
    let table = report_table(&out, "sensitivity");
    assert_eq!(table["name"], "sensitivity");
    let e = |x: f64| x.exp() - 1.0;
    // (output, a, b): log-std of the factor of k and of ρ (studies/sensitivity-jeffcott.toml).
    for (output, a, b) in [
        ("critical_speed_hz:1", 0.1f64, 0.05f64),
        ("sag_vertical_um:centre", 0.2, 0.1),
    ] {
        let (a2, b2) = (a * a, b * b);
        let exact = [
            // (parameter, S, S_T)
            (
                "supports[0].spring.kx_n_per_m",
                e(a2) / e(a2 + b2),
                1.0 - e(b2) / e(a2 + b2),
            ),
            (
                "materials.steel.density_kg_m3",
                e(b2) / e(a2 + b2),
                1.0 - e(a2) / e(a2 + b2),
            ),
            ("speed.hz", 0.0, 0.0),
        ];
        for (param, s, t) in exact {
            let row = rows(&table)
                .into_iter()
                .find(|r| r["output"] == output && r["parameter"] == param)
                .unwrap_or_else(|| panic!("{output} {param}"));
            assert_eq!(num(&row, "n"), 64.0);
            for (col, want) in [("first_order", s), ("total", t)] {
                let (lo, hi) = (
                    num(&row, &format!("{col}_low")),
                    num(&row, &format!("{col}_high")),
                );
                // The speed moves neither output: its estimates are exactly 0.
                let tol = if want == 0.0 { 1e-12 } else { 0.0 };
                eprintln!(
                    "{output} {param} {col}: {} [{lo}, {hi}], closed form {want}",
                    num(&row, col)
                );
                assert!(
                    lo - tol <= want && want <= hi + tol,
                    "{output} {param} {col}: {} [{lo}, {hi}], closed form {want}",
                    num(&row, col)
                );
            }
        }
    }
}

#[test]
fn mean_and_std_of_the_static_sag_under_a_normal_density() {
    // The static sag of the rigid Jeffcott rotor is s = ρ V g/(2k), linear in ρ: with
    // ρ ~ N(7850, 392.5²) it is normal with mean 7850 V g/(2k) and standard deviation
    // 392.5 V g/(2k), V = π (0.1 m)² 0.4 m, k = 1e5 N/m, g = 9.81 m/s² (downward: negative).
    let d = scratch("sample-sag");
    let n = 200;
    let text = jeffcott_study(&format!(
        "[linear]\nspeeds = \"0:1:2\"\nstatic = true\n[sample]\nmethod = \"monte-carlo\"\nn = {n}\nseed = 5\n\
         [[sample.parameters]]\nkey = \"materials.steel.density_kg_m3\"\ndistribution = \"normal\"\nmean = 7850.0\nstd = 392.5\n"
    ));
    let st = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
    let out = d.join("s.h5");
    campaign::run(&st, &support::run_options(&out)).unwrap();
    let per_rho = PI * 0.01 * 0.4 * 9.81 / 2e5 * 1e6; // µm per kg/m³
    let (mean, std) = (-7850.0 * per_rho, 392.5 * per_rho);
    let table = report_table(&out, "statistics");
    let row = rows(&table)
        .into_iter()
        .find(|r| r["output"] == "sag_vertical_um:centre")
        .unwrap();
    assert_eq!(num(&row, "n"), n as f64);
    // The exact values within the table's 95 % bootstrap intervals …
    for (col, exact) in [("mean", mean), ("std", std)] {
        let (lo, hi) = (
            num(&row, &format!("{col}_low")),
            num(&row, &format!("{col}_high")),
        );
        assert!(
            lo <= exact && exact <= hi,
            "{col}: [{lo}, {hi}], exact {exact}"
        );
    }
    // … and the estimates within normal theory's 99 % bounds: the mean within 2.58 σ/√n, the
    // variance within the χ²(n − 1) quantiles 0.5 % and 99.5 % (for 199 degrees of freedom
    // 153.0 and 253.9, Wilson–Hilferty).
    let m = num(&row, "mean");
    eprintln!(
        "sag: mean {m} µm (exact {mean}), std {} µm (exact {std})",
        num(&row, "std")
    );
    assert!(
        (m - mean).abs() < 2.58 * std / (n as f64).sqrt(),
        "{m} against {mean}"
    );
    let ratio = (n - 1) as f64 * (num(&row, "std") / std).powi(2);
    assert!((153.0..253.9).contains(&ratio), "(n − 1) s²/σ² = {ratio}");
    // The intervals reflect n: their half-widths are normal theory's 95 % half-widths,
    // 1.96 s/√n for the mean and 1.96 s/√(2(n − 1)) for the standard deviation of a normal
    // sample (Kendall & Stuart, vol. 1, §10.8), within 20 % (the percentile bootstrap's 1000
    // resamples place a 2.5 % quantile to a few per cent).
    let s = num(&row, "std");
    for (col, theory) in [
        ("mean", 1.96 * s / (n as f64).sqrt()),
        ("std", 1.96 * s / (2.0 * (n - 1) as f64).sqrt()),
    ] {
        let half = (num(&row, &format!("{col}_high")) - num(&row, &format!("{col}_low"))) / 2.0;
        eprintln!("{col}: interval half-width {half} µm, normal theory {theory} µm");
        assert!(
            (half / theory - 1.0).abs() < 0.2,
            "{col}: half-width {half} against {theory}"
        );
    }
}

#[test]
fn sampled_jobs_have_the_same_bytes_at_one_and_two_threads_and_through_shards() {
    let d = scratch("sample-determinism");
    let text = jeffcott_study(
        "[sample]\nmethod = \"saltelli\"\nn = 4\nseed = 9\n\
         [[sample.parameters]]\nkey = \"speed.hz\"\ndistribution = \"uniform\"\nlower = 5.0\nupper = 9.0\n\
         [[sample.parameters]]\nkey = \"materials.steel.density_kg_m3\"\ndistribution = \"lognormal\"\nmean = 7850.0\nstd = 300.0\n",
    );
    let path = write_file(&d, "s.toml", &text);
    let st = Study::load(&path).unwrap();
    assert_eq!(st.jobs.len(), 4 * 4);
    // The same ids when loaded again (a resumed run finds its jobs).
    let again = Study::load(&path).unwrap();
    let ids = |s: &Study| s.jobs.iter().map(|j| j.id.clone()).collect::<Vec<_>>();
    assert_eq!(ids(&st), ids(&again));
    let [one, two, merged] = support::contents_at_one_two_threads_and_shards(&st, &d);
    assert!(
        one.iter().any(|(p, _)| p.ends_with("@speed.hz")),
        "the sample is stored per job"
    );
    assert!(one.iter().any(|(p, _)| p.ends_with("@label:sample")));
    assert_eq!(one, two);
    assert_eq!(one, merged);
}

/// A sampled run killed (SIGKILL) part-way and resumed, again and again, ends with the bytes of
/// an uninterrupted run: the design is a function of the `[sample]` table, so a resumed run
/// asks for the same jobs and finds those saved. (tests/it/study_kill.rs kills a grid study at
/// random moments.)
#[test]
fn a_killed_sampled_run_resumes_to_the_bytes_of_an_uninterrupted_one() {
    use std::time::{Duration, Instant};
    let d = scratch("sample-kill");
    // 64 jobs of 5 s simulated (several seconds in all: several batches of saved runs).
    let text = jeffcott_study(
        "[set]\n\"simulation.t_end_s\" = 5.0\n\
         [sample]\nmethod = \"saltelli\"\nn = 16\nseed = 4\n\
         [[sample.parameters]]\nkey = \"speed.hz\"\ndistribution = \"uniform\"\nlower = 5.0\nupper = 9.0\n\
         [[sample.parameters]]\nkey = \"materials.steel.density_kg_m3\"\ndistribution = \"lognormal\"\nmean = 7850.0\nstd = 300.0\n",
    );
    write_file(&d, "s.toml", &text);
    let run = |out: &str, resume: bool| support::run_command(&d, "s.toml", out, resume);
    assert!(run("whole.h5", false).status().unwrap().success());
    // Batches of saved runs (parts.rs: one file at least every second while runs finish).
    let saved = || support::saved_batches(&d, "out.h5");
    // Each run killed as soon as the saved batches change: it has saved one of its own (or,
    // its runs all done, is assembling the output and removing them). Each resumes the saved
    // jobs and gets further.
    let mut saved_at_kill = Vec::new();
    let t0 = Instant::now();
    while saved_at_kill.len() < 4 && t0.elapsed() < Duration::from_secs(120) {
        let before = saved();
        let mut child = run("out.h5", true).spawn().unwrap();
        while saved() == before && child.try_wait().unwrap().is_none() {
            std::thread::sleep(Duration::from_millis(10));
        }
        child.kill().unwrap();
        if child.wait().unwrap().code().is_some() {
            break; // it finished first
        }
        saved_at_kill.push(saved());
    }
    eprintln!("killed when the saved batches changed; batches then: {saved_at_kill:?}");
    assert!(
        saved_at_kill.len() >= 2,
        "fewer than two runs were killed part-way: {saved_at_kill:?}"
    );
    assert!(run("out.h5", true).status().unwrap().success());
    assert_eq!(
        results_content(&d.join("out.h5")),
        results_content(&d.join("whole.h5"))
    );
}

/// Loads a study of `body` and returns its error's (key, line, text).
fn error_of(body: &str) -> (Option<String>, Option<usize>, String, String) {
    let d = scratch("sample-errors");
    let text = jeffcott_study(body);
    let p = write_file(&d, "s.toml", &text);
    let e = Study::load(&p).unwrap_err();
    assert!(e.to_string().contains("s.toml"), "{e}");
    (e.key.clone(), e.line, e.to_string(), text)
}

fn line(text: &str, needle: &str) -> Option<usize> {
    Some(support::line_number(text, needle))
}

#[test]
fn bad_sample_tables_name_file_key_and_line() {
    let head =
        "[sample]\nmethod = \"monte-carlo\"\nn = 10\n[[sample.parameters]]\nkey = \"speed.hz\"\n";
    let (key, at, msg, text) = error_of(&format!(
        "{head}distribution = \"normal\"\nmean = 7.0\nstd = -0.5\n"
    ));
    assert_eq!(key.as_deref(), Some("sample.parameters[0].std"));
    assert_eq!(at, line(&text, "std = -0.5"));
    assert!(msg.contains("must be positive"), "{msg}");

    let (key, at, msg, text) = error_of(&format!(
        "{head}distribution = \"uniform\"\nlower = 9.0\nupper = 5.0\n"
    ));
    assert_eq!(key.as_deref(), Some("sample.parameters[0].upper"));
    assert_eq!(at, line(&text, "upper = 5.0"));
    assert!(msg.contains("below"), "{msg}");

    let (key, at, msg, text) = error_of(&format!("{head}distribution = \"weibull\"\n"));
    assert_eq!(key.as_deref(), Some("sample.parameters[0].distribution"));
    assert_eq!(at, line(&text, "distribution = \"weibull\""));
    assert!(msg.contains("truncated-normal"), "{msg}");

    let corr = "[sample]\nmethod = \"monte-carlo\"\nn = 10\n\
                correlation = [[1.0, 0.9, 0.9], [0.9, 1.0, -0.9], [0.9, -0.9, 1.0]]\n";
    let params: String = ["speed.hz", "simulation.t_end_s", "solver.hmax"]
        .iter()
        .map(|k| {
            format!(
                "[[sample.parameters]]\nkey = \"{k}\"\ndistribution = \"uniform\"\nlower = 0.1\nupper = 0.2\n"
            )
        })
        .collect();
    let (key, at, msg, text) = error_of(&format!("{corr}{params}"));
    assert_eq!(key.as_deref(), Some("sample.correlation"));
    assert_eq!(
        at,
        line(
            &text,
            "correlation = [[1.0, 0.9, 0.9], [0.9, 1.0, -0.9], [0.9, -0.9, 1.0]]"
        )
    );
    assert!(msg.contains("positive definite"), "{msg}");

    // A sampled key that would replace a [set] key inside it (dropping it silently).
    let replacing = format!(
        "[set]\n\"solver.hmax.x\" = 1.0\n{head}distribution = \"normal\"\nmean = 7.0\nstd = 0.5\n"
    )
    .replace("key = \"speed.hz\"", "key = \"solver.hmax\"");
    let (key, at, msg, text) = error_of(&replacing);
    assert_eq!(key.as_deref(), Some("sample.parameters[0].key"));
    assert_eq!(at, line(&text, "key = \"solver.hmax\""));
    assert!(msg.contains("would replace"), "{msg}");

    let (key, _, msg, _) = error_of(
        "[sample]\nmethod = \"grid\"\nn = 10\n[[sample.parameters]]\nkey = \"speed.hz\"\n\
         distribution = \"normal\"\nmean = 7.0\nstd = 0.5\n",
    );
    assert_eq!(key.as_deref(), Some("sample.method"));
    assert!(msg.contains("latin-hypercube"), "{msg}");

    // A Saltelli design of one parameter: its AB_1 rows are B's (the same jobs), at `method`.
    let (key, at, msg, text) = error_of(
        &format!("{head}distribution = \"normal\"\nmean = 7.0\nstd = 0.5\n")
            .replace("\"monte-carlo\"", "\"saltelli\""),
    );
    assert_eq!(key.as_deref(), Some("sample.method"));
    assert_eq!(at, line(&text, "method = \"saltelli\""));
    assert!(msg.contains("at least two"), "{msg}");

    // Two draws of the same values (a discrete parameter of two values, 10 samples): at the
    // [sample] table, not at axes the study does not have.
    let (key, at, msg, text) = error_of(&format!(
        "{head}distribution = \"discrete\"\nvalues = [5.0, 6.0]\n"
    ));
    assert_eq!(key.as_deref(), Some("sample"));
    assert_eq!(at, line(&text, "[sample]"));
    assert!(
        msg.contains("same values") && msg.contains("discrete"),
        "{msg}"
    );
}

/// The scene's own errors in a sampled value point at the parameter that sampled it.
#[test]
fn a_sampled_value_the_scene_refuses_names_its_parameter() {
    let (key, at, msg, text) = error_of(
        "[sample]\nmethod = \"monte-carlo\"\nn = 4\n[[sample.parameters]]\nkey = \"solver.hmax\"\n\
         distribution = \"uniform\"\nlower = -2.0\nupper = -1.0\n",
    );
    assert_eq!(key.as_deref(), Some("solver.hmax"), "{msg}");
    assert_eq!(at, line(&text, "key = \"solver.hmax\""), "{msg}");
}

#[test]
fn morris_effects_of_a_linear_output_are_its_coefficient_times_the_range() {
    // The static sag s = ρ V g/(2k) (see the test above) is linear in ρ and does not depend on
    // the run's speed. Over ρ uniform on [7000, 8500] every elementary effect (Morris 1991) in
    // the table's unit (per unit probability, so per range) is ds/dρ × 1500 kg/m³: μ = that,
    // μ* = |μ| (Campolongo, Cariboni & Saltelli 2007) and σ = 0; the speed's are all 0. The
    // cylinder's bending, also linear in ρ, adds under 2e-5 of the sag (studies/
    // sensitivity-jeffcott.toml).
    let d = scratch("sample-morris");
    let trajectories = 12;
    let text = jeffcott_study(&format!(
        "[linear]\nspeeds = \"0:1:2\"\nstatic = true\n[sample]\nmethod = \"morris\"\nn = {trajectories}\nlevels = 6\nseed = 11\n\
         [[sample.parameters]]\nkey = \"materials.steel.density_kg_m3\"\ndistribution = \"uniform\"\nlower = 7000.0\nupper = 8500.0\n\
         [[sample.parameters]]\nkey = \"speed.hz\"\ndistribution = \"uniform\"\nlower = 5.0\nupper = 10.0\n"
    ));
    let st = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
    assert_eq!(st.jobs.len(), trajectories * 3);
    let out = d.join("s.h5");
    campaign::run(&st, &support::run_options(&out)).unwrap();
    let per_rho = PI * 0.01 * 0.4 * 9.81 / 2e5 * 1e6; // µm per kg/m³
    let exact = -per_rho * 1500.0;
    let table = report_table(&out, "sensitivity");
    let row = |param: &str| {
        rows(&table)
            .into_iter()
            .find(|r| r["output"] == "sag_vertical_um:centre" && r["parameter"] == param)
            .unwrap_or_else(|| panic!("{param}"))
    };
    let rho = row("materials.steel.density_kg_m3");
    eprintln!(
        "morris: mu {} mu* {} sigma {} (exact mu {exact}, mu* {}, sigma 0)",
        num(&rho, "mu"),
        num(&rho, "mu_star"),
        num(&rho, "sigma"),
        exact.abs()
    );
    assert_eq!(num(&rho, "n"), trajectories as f64);
    assert!((num(&rho, "mu") / exact - 1.0).abs() < 1e-4);
    assert!((num(&rho, "mu_star") / exact.abs() - 1.0).abs() < 1e-4);
    assert!(num(&rho, "sigma") < 1e-6 * exact.abs());
    let speed = row("speed.hz");
    for col in ["mu", "mu_star", "sigma"] {
        assert!(num(&speed, col).abs() < 1e-9 * exact.abs(), "speed {col}");
    }
}

#[test]
fn a_morris_grid_needs_even_levels_and_its_method() {
    for (sample, levels, says) in [
        ("method = \"morris\"\nn = 4\n", "levels = 5", "even"),
        (
            "method = \"sobol\"\nn = 4\n",
            "levels = 4",
            "only with method",
        ),
    ] {
        let (key, at, msg, text) = error_of(&format!(
            "[sample]\n{sample}{levels}\n[[sample.parameters]]\nkey = \"speed.hz\"\ndistribution = \"uniform\"\nlower = 5.0\nupper = 10.0\n"
        ));
        assert_eq!(key.as_deref(), Some("sample.levels"));
        assert_eq!(at, line(&text, levels));
        assert!(msg.contains(says), "{msg}");
    }
}

/// `[sample]` beside a grid axis: n × grid jobs, the same draws at every grid point, and the
/// statistics and Sobol' indices per grid point. The static sag of the rigid Jeffcott rotor,
/// s = ρ V g/(2k) ([`mean_and_std_of_the_static_sag_under_a_normal_density`] derives it), on
/// the axis `simulation.gravity_m_s2` = 9.81 and 4.905 m/s², under ρ ~ N(7850, 392.5²) and a
/// speed uniform on 5 … 10 Hz (which moves no static sag): a Saltelli design of n = 32
/// (n (d + 2) = 128 jobs per point, 256 in all; the statistics use A and B, 64 draws); the
/// second point's job ids those of the plain sampled study at its gravity. Per point: the closed form's mean and standard deviation (g's share) within the table's 95 %
/// intervals; the half-gravity point's mean and standard deviation exactly half the other's
/// (the same draws, an output linear in g: to 1e-9); S_ρ and S_T,ρ = 1 within their intervals,
/// the speed's indices exactly 0. A key both swept and sampled is an error at its
/// `[[sample.parameters]]` entry.
#[test]
fn a_sampled_study_on_a_grid_axis_runs_every_sample_at_every_point() {
    let d = scratch("sample-grid");
    let n = 32;
    let sample = format!(
        "[sample]\nmethod = \"saltelli\"\nn = {n}\nseed = 5\n\
         [[sample.parameters]]\nkey = \"materials.steel.density_kg_m3\"\ndistribution = \"normal\"\nmean = 7850.0\nstd = 392.5\n\
         [[sample.parameters]]\nkey = \"speed.hz\"\ndistribution = \"uniform\"\nlower = 5.0\nupper = 10.0\n"
    );
    let axis = "[[axes]]\nkey = \"simulation.gravity_m_s2\"\nvalues = [9.81, 4.905]\n";
    let text = jeffcott_study(&format!(
        "[linear]\nspeeds = \"0:1:2\"\nstatic = true\n{axis}{sample}"
    ));
    let st = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
    assert_eq!(st.jobs.len(), 2 * n * 4);
    // The same draws at both points: job i of the second half has job i's density.
    let rho = values(&st, "materials.steel.density_kg_m3");
    assert_eq!(rho[..n * 4], rho[n * 4..]);
    // Ids from the scenes: the second point's jobs are those of the plain sampled study at
    // that gravity (so adding or removing a grid point, a resume or a shard keeps them).
    let plain = jeffcott_study(&format!(
        "[linear]\nspeeds = \"0:1:2\"\nstatic = true\n[set]\n\"simulation.gravity_m_s2\" = 4.905\n{sample}"
    ));
    let plain = Study::load(&write_file(&d, "plain.toml", &plain)).unwrap();
    let ids = |jobs: &[rotorsweep::study::Job]| -> Vec<String> {
        jobs.iter().map(|j| j.id.clone()).collect()
    };
    assert_eq!(ids(&st.jobs[n * 4..]), ids(&plain.jobs));
    let out = d.join("s.h5");
    campaign::run(&st, &support::run_options(&out)).unwrap();
    let sag_rows = |table: &str| -> Vec<_> {
        rows(&report_table(&out, table))
            .into_iter()
            .filter(|r| r["output"] == "sag_vertical_um:centre")
            .collect()
    };
    let stats = sag_rows("statistics");
    assert_eq!(stats.len(), 2, "one row per grid point");
    let mut means = Vec::new();
    for (row, g) in stats.iter().zip([9.81, 4.905]) {
        assert_eq!(num(row, "simulation.gravity_m_s2"), g);
        assert_eq!(num(row, "n"), (2 * n) as f64);
        let per_rho = PI * 0.01 * 0.4 * g / 2e5 * 1e6; // µm per kg/m³
        for (col, exact) in [("mean", -7850.0 * per_rho), ("std", 392.5 * per_rho)] {
            let (lo, hi) = (
                num(row, &format!("{col}_low")),
                num(row, &format!("{col}_high")),
            );
            assert!(
                lo <= exact && exact <= hi,
                "g {g} {col}: [{lo}, {hi}], exact {exact}"
            );
        }
        means.push((num(row, "mean"), num(row, "std")));
    }
    assert!((means[1].0 / means[0].0 - 0.5).abs() < 1e-9, "{means:?}");
    assert!((means[1].1 / means[0].1 - 0.5).abs() < 1e-9, "{means:?}");
    let indices = sag_rows("sensitivity");
    assert_eq!(indices.len(), 4, "2 grid points × 2 parameters");
    for row in &indices {
        let g = num(row, "simulation.gravity_m_s2");
        assert!(g == 9.81 || g == 4.905, "{row:?}");
        let want = if row["parameter"] == "speed.hz" {
            0.0
        } else {
            1.0
        };
        for col in ["first_order", "total"] {
            let (lo, hi) = (
                num(row, &format!("{col}_low")),
                num(row, &format!("{col}_high")),
            );
            let tol = if want == 0.0 { 1e-12 } else { 0.0 };
            assert!(lo - tol <= want && want <= hi + tol, "{row:?}");
        }
    }
    // The samples table: every job, the grid point's gravity beside the sampled density, each
    // job's sag the rigid body's closed form at its own ρ and g, to 2e-5 (the cylinder's own
    // bending, also linear in ρ g, adds under 2e-5 of the sag: studies/sensitivity-jeffcott.toml).
    let samples = report_table(&out, "samples");
    assert_eq!(
        samples["columns"].as_array().unwrap()[..4],
        [
            "job_id",
            "label",
            "simulation.gravity_m_s2",
            "materials.steel.density_kg_m3"
        ]
    );
    let all = rows(&samples);
    assert_eq!(all.len(), 2 * n * 4);
    for (i, row) in all.iter().enumerate() {
        let g = num(row, "simulation.gravity_m_s2");
        assert_eq!(g, if i < n * 4 { 9.81 } else { 4.905 }, "{row:?}");
        let rho = num(row, "materials.steel.density_kg_m3");
        let exact = -rho * PI * 0.01 * 0.4 * g / 2e5 * 1e6;
        let sag = num(row, "sag_vertical_um:centre");
        assert!((sag / exact - 1.0).abs() < 2e-5, "{sag} against {exact}");
    }
    // A key both swept and sampled.
    let both = jeffcott_study(&format!(
        "[[axes]]\nkey = \"speed.hz\"\nvalues = [5.0, 6.0]\n{sample}"
    ));
    let e = Study::load(&write_file(&d, "both.toml", &both)).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("sample.parameters[1].key"), "{e}");
    let lines: Vec<&str> = both.lines().collect();
    let at = lines.iter().rposition(|l| *l == "key = \"speed.hz\"");
    assert_eq!(e.line, at.map(|i| i + 1), "{e}");
    assert!(
        e.to_string().contains("swept on axes[0] and sampled"),
        "{e}"
    );
}

/// Explicit `[[jobs]]` beside a `[sample]` (the static sag under a normal density, as in
/// `mean_and_std_of_the_static_sag_under_a_normal_density`): each runs once after the design
/// with its own overrides and no design row, the design's jobs keep their ids, and the
/// statistics and samples tables read the design alone, so they are those of the same study
/// without the explicit jobs, cell for cell. An explicit job's bad value of a sampled key is
/// reported at its own line, not at the parameter that samples the key.
#[test]
fn explicit_jobs_beside_a_sample_run_once_and_stay_out_of_its_tables() {
    let d = scratch("sample-explicit-jobs");
    let sample = "[linear]\nspeeds = \"0:1:2\"\nstatic = true\n\
                  [sample]\nmethod = \"monte-carlo\"\nn = 8\nseed = 5\n\
                  [[sample.parameters]]\nkey = \"materials.steel.density_kg_m3\"\n\
                  distribution = \"normal\"\nmean = 7850.0\nstd = 392.5\n";
    let jobs =
        "[[jobs]]\n\"materials.steel.density_kg_m3\" = 20000.0\n[[jobs]]\n\"speed.hz\" = 7.0\n";
    let plain = Study::load(&write_file(&d, "plain.toml", &jeffcott_study(sample))).unwrap();
    let mixed = Study::load(&write_file(
        &d,
        "mixed.toml",
        &jeffcott_study(&format!("{sample}{jobs}")),
    ))
    .unwrap();
    assert_eq!(mixed.jobs.len(), 8 + 2);
    let ids = |s: &Study| s.jobs.iter().map(|j| j.id.clone()).collect::<Vec<_>>();
    assert_eq!(ids(&mixed)[..8], ids(&plain)[..]);
    let value = |i: usize, k: &str| mixed.value_of(&mixed.jobs[i], k).and_then(|v| v.as_float());
    assert_eq!(value(8, "materials.steel.density_kg_m3"), Some(20000.0));
    assert_eq!(value(9, "speed.hz"), Some(7.0));
    let (p_out, m_out) = (d.join("plain.h5"), d.join("mixed.h5"));
    campaign::run(&plain, &support::run_options(&p_out)).unwrap();
    campaign::run(&mixed, &support::run_options(&m_out)).unwrap();
    let jobs_in = |f: &std::path::Path| {
        results_content(f)
            .iter()
            .filter(|(p, _)| p.ends_with("@status"))
            .count()
    };
    assert_eq!(jobs_in(&m_out), 10);
    for table in ["statistics", "samples"] {
        let (a, b) = (report_table(&p_out, table), report_table(&m_out, table));
        assert_eq!(a["columns"], b["columns"], "{table}");
        assert_eq!(a["rows"], b["rows"], "{table}");
    }
    assert_eq!(rows(&report_table(&m_out, "samples")).len(), 8);
    let (key, at, msg, text) = error_of(&format!(
        "{sample}[[jobs]]\n\"materials.steel.density_kg_m3\" = -1.0\n"
    ));
    assert_eq!(
        key.as_deref(),
        Some("materials.steel.density_kg_m3"),
        "{msg}"
    );
    assert_eq!(
        at,
        line(&text, "\"materials.steel.density_kg_m3\" = -1.0"),
        "{msg}"
    );
}
