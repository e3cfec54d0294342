//! `rotorsweep report --format html` and `rotorsweep simulate -o` through the command line.
//!
//! - `simulate -o` writes the layout of one study job (the attributes a study job has, its
//!   mean and spectrum, `/analysis`, `/summary`), so that `report` reads it; the numbers are
//!   checked against the scene file (studies/scenes/timing-case.toml: 16.4 Hz, journals Ø115 mm
//!   on rollers Ø125 mm) and against the record itself (its mean, computed here).
//! - The HTML report of a small study (the reference roll, 0.1 s per job as `study_text` sets,
//!   3 speeds × 2 integrators against a tight BDF reference): one self-contained page (no
//!   external resource, the figures embedded as PNG), written by the output rules of
//!   `store::output` (refuses an existing file without `--overwrite`, and a file it did not
//!   write even with it; nothing left under the working names), and rendered by headless
//!   Chromium into a PNG that is not blank. The figures need a Python with the packages of
//!   scripts/requirements.txt (`$ROTORSWEEP_PYTHON`, or the repo's `.venv` that
//!   scripts/python-test makes); without one the page is made with `--no-figures` and the test
//!   says so. Chromium is Debian's (`apt-get install -y chromium`, tried here when missing and
//!   run as root); the screenshot part is skipped with a message where it cannot be had.

use crate::support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use base64::Engine as _;
use rotorsweep::study::run as campaign;
use rotorsweep::study::Study;
use support::{repo, scratch, study_text, write_file};

fn rotorsweep(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args(args)
        .output()
        .expect("run rotorsweep")
}

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "exit {:?}: {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn num(g: &hdf5::Group, name: &str) -> f64 {
    g.attr(name)
        .and_then(|a| a.read_scalar::<f64>())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn simulate_output_has_the_layout_of_a_study_job() {
    let d = scratch("simulate-layout");
    let out = d.join("sim.h5");
    let scene = repo().join("studies/scenes/timing-case.toml");
    let path = |p: &Path| p.display().to_string();
    ok(&rotorsweep(&[
        "simulate",
        &path(&scene),
        "--set",
        "simulation.t_end_s=0.6",
        "--set",
        "simulation.settle_s=0.3",
        "--set",
        "supports[0].roller_phase=roller-angle",
        "-o",
        &path(&out),
    ]));
    {
        let f = hdf5::File::open(&out).unwrap();
        let text = |loc: &hdf5::Location, name: &str| -> String {
            loc.attr(name)
                .and_then(|a| a.read_scalar::<hdf5::types::VarLenUnicode>())
                .map(|v| v.to_string())
                .unwrap_or_else(|e| panic!("{name}: {e}"))
        };
        assert_eq!(text(&f, "study_name"), "timing-case");
        assert_eq!(text(&f, "varying_keys"), "");
        let g = f.group("jobs/timing-case").unwrap();
        // As a study job: its index and kind, the speed over the record (the scene's 16.4 Hz)
        // and the roll angle's offset (0: constant from t = 0).
        assert_eq!(
            g.attr("job_index").unwrap().read_scalar::<u64>().unwrap(),
            0
        );
        assert_eq!(text(&g, "kind"), "job");
        assert_eq!(num(&g, "speed_hz"), 16.4);
        assert_eq!(num(&g, "roll_angle_offset_rad"), 0.0);
        // The rollers' line ratios: the tending side follows the rollers' own angle,
        // journal/roller = 115/125 = 0.92; the drive side the roll angle, 1.
        for r in ["front", "rear"] {
            let t = num(&g, &format!("roller_ratio:journal_tending/{r}"));
            assert!((t - 115.0 / 125.0).abs() < 1e-12, "{t}");
            assert_eq!(num(&g, &format!("roller_ratio:journal_drive/{r}")), 1.0);
        }
        // The mean apart (the static sag under gravity: the roll hangs down, some hundred µm),
        // equal to the record's own mean; the spectrum of the rest: nothing of the sag at 0 Hz
        // or in the next bin.
        let x: Vec<f64> = g
            .dataset("runout/centre/vertical")
            .unwrap()
            .read_raw()
            .unwrap();
        let mean = x.iter().sum::<f64>() / x.len() as f64;
        let stored = g
            .dataset("runout_mean/centre/vertical")
            .unwrap()
            .read_scalar::<f64>()
            .unwrap();
        assert!(
            (stored - mean).abs() < 1e-9 * mean.abs(),
            "{stored} vs {mean}"
        );
        assert!(mean < -100.0, "sag {mean} µm");
        let spec: Vec<f64> = g
            .dataset("spectrum/centre/vertical")
            .unwrap()
            .read_raw()
            .unwrap();
        assert!(
            spec[0] < 1e-2 * mean.abs() && spec[1] < 1e-2 * mean.abs(),
            "{:?}",
            &spec[..3]
        );
        // Up to 1.25 × the highest default order (4) × 16.4 Hz = 82 Hz, in bins of 1000/301 Hz
        // (0.3 s at 1 kHz: 301 samples).
        let freq: Vec<f64> = g.dataset("spectrum/freq_hz").unwrap().read_raw().unwrap();
        let top = freq[freq.len() - 1];
        assert!(top <= 82.0 && top > 82.0 - 1000.0 / 301.0, "{top}");
        // The analysis and summary as `run` writes them: 6 runout channels × orders 1–4.
        assert_eq!(f.dataset("analysis/lines").unwrap().shape(), vec![24]);
        assert_eq!(f.dataset("summary").unwrap().shape(), vec![1]);
    }
    // `report` reads it as a study's: one job, ok, in the solver table.
    let json: serde_json::Value = serde_json::from_str(&ok(&rotorsweep(&[
        "report",
        &path(&out),
        "--format",
        "json",
    ])))
    .unwrap();
    let solver = &json["tables"][0];
    assert_eq!(solver["name"], "solver");
    assert_eq!(solver["rows"].as_array().unwrap().len(), 1);
    assert_eq!(solver["rows"][0][0], "timing-case", "job_id first");
}

/// A Python that can draw the figures (module doc), if any.
fn figure_python() -> Option<PathBuf> {
    let candidates: Vec<PathBuf> = std::env::var_os("ROTORSWEEP_PYTHON")
        .map(PathBuf::from)
        .into_iter()
        .chain([repo().join(".venv/bin/python")])
        .collect();
    candidates.into_iter().find(|p| {
        Command::new(p)
            .args(["-c", "import h5py, matplotlib, pandas, xarray, h5netcdf"])
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// Debian's Chromium, installed here when missing (as root, with apt-get), if it can be had.
fn chromium() -> Option<PathBuf> {
    let found = || {
        ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
            .iter()
            .map(PathBuf::from)
            .find(|p| p.is_file())
    };
    if let Some(p) = found() {
        return Some(p);
    }
    let root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    if root && Path::new("/usr/bin/apt-get").exists() {
        eprintln!("report_html: installing chromium (apt-get install -y chromium)");
        let install = || {
            Command::new("apt-get")
                .args(["install", "-y", "-q", "chromium"])
                .env("DEBIAN_FRONTEND", "noninteractive")
                .output()
                .is_ok_and(|o| o.status.success())
        };
        if !install() {
            let _ = Command::new("apt-get").args(["update", "-q"]).output();
            install();
        }
    }
    found()
}

/// Share of pixels of an RGB(A) PNG that are not (near) white, and its number of distinct
/// colours (quantised to 4 bits a channel).
fn ink(png_path: &Path) -> (f64, usize) {
    let decoder = png::Decoder::new(std::fs::File::open(png_path).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    assert!(channels >= 3, "{:?}", info.color_type);
    let px: Vec<&[u8]> = buf[..info.buffer_size()].chunks(channels).collect();
    let dark = px
        .iter()
        .filter(|p| p[..3].iter().any(|c| *c < 235))
        .count();
    let colours: std::collections::BTreeSet<[u8; 3]> = px
        .iter()
        .map(|p| [p[0] >> 4, p[1] >> 4, p[2] >> 4])
        .collect();
    (dark as f64 / px.len() as f64, colours.len())
}

#[test]
fn html_report_is_self_contained_and_follows_the_output_rules() {
    let d = scratch("report-html");
    let study = Study::load(&write_file(
        &d,
        "s.toml",
        &study_text(
            "[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 14.0, 16.0]\n\
             [[axes]]\nkey = \"solver.integrator\"\nvalues = [\"bdf\", \"gen-alpha\"]\n\
             [reference]\n\"solver.integrator\" = \"bdf\"\n\"solver.tolerance\" = 1e-10\n\
             \"solver.hmax\" = 2e-5\n",
        ),
    ))
    .unwrap();
    let results = d.join("out.h5");
    assert_eq!(
        campaign::run(&study, &support::run_options(&results))
            .unwrap()
            .ok,
        6
    );
    let html_path = d.join("report.html");
    let (r, h) = (
        results.display().to_string(),
        html_path.display().to_string(),
    );
    let python = figure_python();
    let mut args = vec!["report", &r, "--format", "html", "-o", &h];
    // The figures are drawn in a temporary folder of the report's own, under TMPDIR: none may
    // be left there.
    let tmp = d.join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let run_html = |args: &[&str]| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_rotorsweep"));
        c.args(args).env("TMPDIR", &tmp);
        if let Some(p) = &python {
            c.env("ROTORSWEEP_PYTHON", p);
        }
        c.output().expect("run rotorsweep")
    };
    if python.is_none() {
        eprintln!(
            "report_html: no Python with h5py, matplotlib, pandas, xarray and h5netcdf (set ROTORSWEEP_PYTHON or \
             run scripts/python-test first): the page is made with --no-figures"
        );
        args.push("--no-figures");
    }
    assert!(run_html(&args).status.success());
    let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().collect();
    assert!(left.is_empty(), "left in TMPDIR: {left:?}");
    let html = std::fs::read_to_string(&html_path).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert!(html.contains(rotorsweep::report::HTML_MARKER));
    // Every table, under its own section with its legend.
    for t in ["solver", "resonances", "stability", "linear"] {
        assert!(html.contains(&format!("<section id=\"{t}\">")), "{t}");
    }
    assert!(html.matches("<p class=\"legend\">").count() >= 4);
    // Self-contained: nothing fetched from elsewhere.
    for external in ["src=\"http", "href=\"http", "<script", "<link", "url("] {
        assert!(!html.contains(external), "{external}");
    }
    // The figures embedded: each a PNG (its signature after base64 decoding).
    let figures: Vec<&str> = html.split("src=\"data:image/png;base64,").skip(1).collect();
    if python.is_some() {
        assert!(figures.len() >= 4, "{} figures", figures.len());
        for f in &figures {
            let b64 = &f[..f.find('"').unwrap()];
            let png = base64::engine::general_purpose::STANDARD
                .decode(b64)
                .unwrap();
            assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        }
        for name in [
            "work_precision.png",
            "timing.png",
            "stability.png",
            "campbell.png",
        ] {
            assert!(html.contains(&format!("alt=\"{name}\"")), "{name}");
        }
    }
    // The output rules: an existing page is kept without --overwrite (exit 64), replaced with
    // it; a file rotorsweep did not write, or a folder, is never replaced; nothing is left
    // under the working names.
    let again = run_html(&args);
    assert_eq!(again.status.code(), Some(64));
    assert!(String::from_utf8_lossy(&again.stderr).contains("exists"));
    let mut over = args.clone();
    over.push("--overwrite");
    assert!(run_html(&over).status.success());
    let replace = |target: &Path| {
        let t = target.display().to_string();
        rotorsweep(&[
            "report",
            &r,
            "--format",
            "html",
            "--no-figures",
            "-o",
            &t,
            "--overwrite",
        ])
    };
    let notes = write_file(&d, "notes.html", "<html>my notes</html>\n");
    assert_eq!(replace(&notes).status.code(), Some(64));
    assert_eq!(
        std::fs::read_to_string(&notes).unwrap(),
        "<html>my notes</html>\n"
    );
    assert_eq!(replace(&d).status.code(), Some(64), "a folder");
    let md_to_file = rotorsweep(&["report", &r, "-o", &h]);
    assert_eq!(
        md_to_file.status.code(),
        Some(64),
        "-o is for the HTML page"
    );
    for leftover in ["report.html.tmp", "report.html.lock", "notes.html.tmp"] {
        assert!(!d.join(leftover).exists(), "{leftover}");
    }
    // In a real browser: headless Chromium renders the page to a PNG with ink on it.
    match chromium() {
        None => eprintln!(
            "report_html: SKIPPED the Chromium rendering: no /usr/bin/chromium and it could not \
             be installed (apt-get install -y chromium)"
        ),
        Some(browser) => {
            let shot = d.join("report.png");
            let out = Command::new(&browser)
                .args([
                    "--headless",
                    "--no-sandbox",
                    "--disable-gpu",
                    "--hide-scrollbars",
                    "--window-size=1400,3000",
                    &format!("--screenshot={}", shot.display()),
                    &format!("file://{}", html_path.display()),
                ])
                .output()
                .expect("run chromium");
            assert!(
                shot.is_file(),
                "no screenshot: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let (share, colours) = ink(&shot);
            // Tables and text alone cover a few per cent; the figures add colour.
            assert!(share > 0.01, "{share} of the page inked");
            if python.is_some() {
                assert!(colours > 50, "{colours} colours");
            }
        }
    }
}

/// Without a Python that has the figures package the page is still written, with its tables and
/// one line saying how to get the figures (it never fails for want of Python); a figure process
/// past its time limit is stopped, the report fails, and nothing is left in TMPDIR.
#[test]
fn html_report_without_python_or_past_the_time_limit() {
    let d = scratch("report-html-no-python");
    let h5 = d.join("run.h5");
    let scene = repo().join("studies/scenes/timing-case.toml");
    ok(&rotorsweep(&[
        "simulate",
        scene.to_str().unwrap(),
        "--set",
        "simulation.t_end_s=0.2",
        "-o",
        h5.to_str().unwrap(),
    ]));
    let tmp = d.join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let page = d.join("page.html");
    let report = |python: &Path, limit: &str| {
        Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
            .args(["report", h5.to_str().unwrap(), "--format", "html", "-o"])
            .arg(&page)
            .arg("--overwrite")
            .env("TMPDIR", &tmp)
            .env("ROTORSWEEP_PYTHON", python)
            .env("ROTORSWEEP_FIGURES_TIMEOUT_S", limit)
            .output()
            .expect("run rotorsweep")
    };
    let out = report(&d.join("no-such-python"), "600");
    ok(&out);
    let hint = "pip install \"./python[figures]\"";
    assert!(String::from_utf8_lossy(&out.stderr).contains(hint));
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains("Figures: none drawn"), "the page says why");
    assert!(
        html.contains("<section id=\"solver\">"),
        "the page has its tables"
    );
    assert!(!html.contains("data:image/png"));
    if let Some(python) = figure_python() {
        let out = report(&python, "0.001");
        assert_eq!(out.status.code(), Some(1));
        assert!(String::from_utf8_lossy(&out.stderr).contains("took longer than 0.001 s"));
    }
    let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().collect();
    assert!(left.is_empty(), "left in TMPDIR: {left:?}");
}
