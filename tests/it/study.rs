//! The study engine: expansion and validation of study files, and bit-identical job datasets at 1
//! and 2 threads and through 2 shards + merge (crash safety is in tests/it/study_kill.rs).

use crate::support;

use std::path::Path;

use rotorsweep::study::merge;
use rotorsweep::study::run::{self as campaign, ReferenceSource, RunOptions};
use rotorsweep::study::Study;
use support::{scratch, study_text, write_file};

pub(crate) fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}

#[test]
fn expansion_product_zip_range_and_explicit_jobs() {
    let d = scratch("expand");
    let text = study_text(
        "[[axes]]\nkey = \"speed.hz\"\nrange = { start = 10.0, stop = 11.0, step = 0.5 }\n\
         [[axes]]\nkeys = [\"solver.integrator\", \"solver.hmax\"]\nvalues = [[\"bdf\", 1e-4], [\"gen-alpha\", 2e-4]]\n\
         [[jobs]]\n\"speed.hz\" = 16.4\n",
    );
    let st = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
    // 3 speeds × 2 zipped rows + 1 explicit job.
    assert_eq!(st.jobs.len(), 7);
    assert_eq!(
        st.varying,
        vec!["speed.hz", "solver.integrator", "solver.hmax"]
    );
    let speeds: Vec<f64> = st
        .jobs
        .iter()
        .map(|j| st.value_of(j, "speed.hz").unwrap().as_float().unwrap())
        .collect();
    assert_eq!(speeds, vec![10.0, 10.0, 10.5, 10.5, 11.0, 11.0, 16.4]);
    // Zipped keys move together.
    assert_eq!(
        st.value_of(&st.jobs[1], "solver.integrator")
            .unwrap()
            .as_str(),
        Some("gen-alpha")
    );
    assert_eq!(
        st.value_of(&st.jobs[1], "solver.hmax").unwrap().as_float(),
        Some(2e-4)
    );
    // Ids are stable and distinct; the same file expands to the same ids.
    let again = Study::load(&d.join("s.toml")).unwrap();
    let ids: Vec<&str> = st.jobs.iter().map(|j| j.id.as_str()).collect();
    assert_eq!(
        ids,
        again.jobs.iter().map(|j| j.id.as_str()).collect::<Vec<_>>()
    );
    let unique: std::collections::BTreeSet<&str> = ids.iter().copied().collect();
    assert_eq!(unique.len(), 7);
    // One model for all (no model key varies); shards split by index.
    assert!(st.jobs.iter().all(|j| j.model_id == st.jobs[0].model_id));
    assert_eq!(st.shard(0, 2).len() + st.shard(1, 2).len(), 7);
}

#[test]
fn validation_errors_name_the_study_file_line_and_key() {
    let d = scratch("errors");
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "duplabel.toml",
            study_text(
                "[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0, 12.0]\nlabels = [\"a\", \"a\"]\n",
            ),
            "labels = [",
            "given twice",
        ),
        (
            "nobaseline.toml",
            study_text(
                "[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0]\n[analysis]\nbaseline = \"ref\"\n",
            ),
            "baseline = ",
            "no axis has the label `ref`",
        ),
        (
            // 3 × 200 Hz = 600 Hz is above the 500 Hz Nyquist frequency of 1 kHz sampling.
            "nyquist.toml",
            study_text(
                "[[axes]]\nkey = \"speed.hz\"\nvalues = [200.0]\n[analysis]\norders = [1.0, 3.0]\n",
            ),
            "orders = ",
            "Nyquist",
        ),
        (
            "duporder.toml",
            study_text(
                "[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0]\n[analysis]\norders = [1.0, 1.0]\n",
            ),
            "orders = ",
            "given twice",
        ),
        (
            "unknown.toml",
            study_text("colour = \"red\"\n"),
            "colour",
            "unknown field",
        ),
        (
            "badvalue.toml",
            study_text("[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0, -5.0]\n"),
            "values = [10.0, -5.0]",
            "speed.hz",
        ),
        (
            "badkey.toml",
            study_text("[[axes]]\nkey = \"solver.hmaxx\"\nvalues = [1e-4]\n"),
            "values = [1e-4]",
            "hmaxx",
        ),
        (
            "noval.toml",
            study_text("[[axes]]\nkey = \"speed.hz\"\n"),
            "[[axes]]",
            "values",
        ),
        (
            "refphys.toml",
            study_text(
                "[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0]\n[reference]\n\"speed.hz\" = 3.0\n",
            ),
            "\"speed.hz\" = 3.0",
            "solver",
        ),
    ];
    for (name, text, needle, reason) in cases {
        let p = write_file(&d, name, &text);
        let e = Study::load(&p).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains(name), "{name}: {msg}");
        assert!(msg.contains(reason), "{name}: {msg}");
        let want = line_of(&text, needle);
        assert_eq!(e.line, Some(want), "{name}: {msg}");
    }
    // A missing scene file is named.
    let p = write_file(
        &d,
        "noscene.toml",
        "scene = \"nope.toml\"\n[[axes]]\nkey = \"speed.hz\"\nvalues = [1.0]\n",
    );
    let e = Study::load(&p).unwrap_err();
    assert!(e.to_string().contains("nope.toml"), "{e}");
    assert_eq!(e.line, Some(1));
}

fn run_study(study: &Study, out: &Path, threads: usize, shard: Option<(usize, usize)>) {
    let opts = RunOptions {
        output: out.to_path_buf(),
        threads,
        resume: false,
        overwrite: false,
        shard,
        command: "test".into(),
        references: Default::default(),
    };
    campaign::run(study, &opts).unwrap();
}

/// Every dataset under `group` by path: floats as raw f64 bits, strings as their bytes.
fn group_data(path: &Path, group: &str) -> Vec<(String, Vec<u64>)> {
    fn walk(g: &hdf5::Group, prefix: &str, out: &mut Vec<(String, Vec<u64>)>) {
        for name in g.member_names().unwrap() {
            let p = format!("{prefix}/{name}");
            if let Ok(sub) = g.group(&name) {
                walk(&sub, &p, out);
            } else {
                let ds = g.dataset(&name).unwrap();
                let bits: Vec<u64> = match ds.read_raw::<f64>() {
                    Ok(v) => v.iter().map(|x| x.to_bits()).collect(),
                    Err(_) => ds
                        .read_raw::<hdf5::types::VarLenUnicode>()
                        .unwrap()
                        .iter()
                        .flat_map(|s| s.as_str().bytes().map(u64::from))
                        .collect(),
                };
                out.push((p, bits));
            }
        }
    }
    let f = hdf5::File::open(path).unwrap();
    let mut out = Vec::new();
    walk(&f.group(group).unwrap(), "", &mut out);
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

#[test]
fn same_bytes_at_one_and_two_threads_and_through_shards_and_merge() {
    let d = scratch("determinism");
    let text = study_text(
        "[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 16.0]\n[[axes]]\nkey = \"solver.hmax\"\nvalues = [1e-4, 3e-4]\n\
         [reference]\n\"solver.hmax\" = 5e-5\n",
    );
    let st = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
    run_study(&st, &d.join("one.h5"), 1, None);
    run_study(&st, &d.join("two.h5"), 2, None);
    run_study(&st, &d.join("s0.h5"), 2, Some((0, 2)));
    run_study(&st, &d.join("s1.h5"), 2, Some((1, 2)));
    merge::merge(
        &[d.join("s0.h5"), d.join("s1.h5")],
        &d.join("merged.h5"),
        &merge::MergeOptions::default(),
    )
    .unwrap();
    let job_data = |p: &Path| group_data(p, "jobs");
    let one = job_data(&d.join("one.h5"));
    assert_eq!(
        one.len(),
        4 * 26,
        "4 jobs × (time + 6 runout channels + 6 means + spectrum frequencies + 6 spectra, and \
         time and the frequencies linked into the 3 runout and 3 spectrum groups as their axes)"
    );
    assert_eq!(one, job_data(&d.join("two.h5")));
    assert_eq!(one, job_data(&d.join("merged.h5")));
    // The linearised systems (Campbell data, critical speeds) too.
    let linear = group_data(&d.join("one.h5"), "linear");
    assert_eq!(
        linear.len(),
        11,
        "one system: Campbell speeds, modes, whirl_hz, log_dec, damping_ratio, whirl_index, \
         whirl, branch; critical speeds with their log dec and whirl"
    );
    assert_eq!(linear, group_data(&d.join("two.h5"), "linear"));
    assert_eq!(linear, group_data(&d.join("merged.h5"), "linear"));
    // The analysis: made on the workers from the runs in memory in `one` and `two`, read back
    // from the shard files by the merge: the lines and the order tracking of every job, bit for
    // bit (two speeds make no sweep).
    // A swap of two channels' rows (a wrong link order) changes a job's sequence of amplitudes;
    // the jobs are listed in each file's job order, so they are compared by id.
    let rows = |p: &str, table: &str| -> Vec<(String, [u64; 3])> {
        let f = hdf5::File::open(d.join(p)).unwrap();
        let ds = f.dataset(&format!("analysis/{table}")).unwrap();
        let rows: Vec<AnalysisRow> = ds.read_raw().unwrap();
        let mut rows: Vec<(String, [u64; 3])> = (rows.iter())
            .map(|r| {
                let bits = [r.order, r.amplitude_um, r.phase_deg].map(f64::to_bits);
                (r.job_id.to_string(), bits)
            })
            .collect();
        rows.sort_by(|a, b| a.0.cmp(&b.0));
        rows
    };
    for table in ["lines", "orders"] {
        let one = rows("one.h5", table);
        assert!(
            one.len() >= 4 * 2 * 3,
            "{table}: 4 jobs × 2 channels × 3 orders"
        );
        assert_eq!(one, rows("two.h5", table), "{table}");
        assert_eq!(one, rows("merged.h5", table), "{table}");
    }
    // The merged summary has every job once, in job order.
    let f = hdf5::File::open(d.join("merged.h5")).unwrap();
    let n = f.dataset("summary").unwrap().shape()[0];
    assert_eq!(n, 4);
}

/// Runs `study` into `out` on 2 threads with its reference runs from `references`.
fn run_with(
    study: &Study,
    out: &Path,
    shard: Option<(usize, usize)>,
    references: ReferenceSource,
) -> Result<campaign::Outcome, campaign::CampaignError> {
    let opts = RunOptions {
        output: out.to_path_buf(),
        threads: 2,
        resume: false,
        overwrite: false,
        shard,
        command: "test".into(),
        references,
    };
    campaign::run(study, &opts)
}

#[test]
fn shards_sharing_one_references_file_give_the_unsharded_results() {
    let d = scratch("shared-references");
    let body = "[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 16.0]\n[[axes]]\nkey = \"solver.hmax\"\nvalues = [1e-4, 3e-4]\n\
                [reference]\n\"solver.hmax\" = 5e-5\n";
    let st = Study::load(&write_file(&d, "s.toml", &study_text(body))).unwrap();
    run_study(&st, &d.join("one.h5"), 2, None);
    let refs = d.join("refs.h5");
    let only = run_with(&st, &refs, None, ReferenceSource::Only).unwrap();
    assert_eq!((only.jobs, only.references_failed), (0, 0));
    let shared = ReferenceSource::File(refs.clone());
    for i in 0..2 {
        run_with(
            &st,
            &d.join(format!("s{i}.h5")),
            Some((i, 2)),
            shared.clone(),
        )
        .unwrap();
    }
    merge::merge(
        &[d.join("s0.h5"), d.join("s1.h5")],
        &d.join("merged.h5"),
        &merge::MergeOptions::default(),
    )
    .unwrap();
    // The references file: the study's reference runs (one per speed) and linearised system as
    // an unsharded run computes them, no job.
    for group in ["references", "linear"] {
        assert_eq!(
            group_data(&refs, group),
            group_data(&d.join("one.h5"), group)
        );
    }
    assert!(group_data(&refs, "jobs").is_empty());
    // The merged shards hold what the unsharded run does, bit for bit.
    for group in ["jobs", "references", "linear", "models"] {
        let one = group_data(&d.join("one.h5"), group);
        assert!(!one.is_empty(), "{group}");
        assert_eq!(one, group_data(&d.join("merged.h5"), group), "{group}");
    }

    // A references file of other inputs is refused before anything runs, naming what changed.
    let other_text = study_text(&body.replace("5e-5", "4e-5"));
    let other = Study::load(&write_file(&d, "t.toml", &other_text)).unwrap();
    let e = run_with(&other, &d.join("t0.h5"), Some((0, 2)), shared.clone()).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("refs.h5") && msg.contains("other inputs"),
        "{msg}"
    );
    assert!(!d.join("t0.h5").exists() && !d.join("t0.h5.parts").exists());
    // A shard file is not a references file; a references file is not a shard to merge.
    let e = run_with(
        &st,
        &d.join("u.h5"),
        None,
        ReferenceSource::File(d.join("s0.h5")),
    );
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("is not a references file"));
    let e = merge::merge(
        &[refs.clone(), d.join("s0.h5")],
        &d.join("m2.h5"),
        &merge::MergeOptions::default(),
    );
    assert!(e.unwrap_err().to_string().contains("is a references file"));
    // Without a [reference] section there is nothing to share.
    let plain = Study::load(&write_file(&d, "p.toml", &study_text(""))).unwrap();
    let e = run_with(&plain, &d.join("p.h5"), None, ReferenceSource::Only).unwrap_err();
    assert!(e.to_string().contains("no [reference] section"), "{e}");
}

/// Columns that `/analysis/lines` and `/analysis/orders` share.
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct AnalysisRow {
    job_id: hdf5::types::VarLenUnicode,
    order: f64,
    amplitude_um: f64,
    phase_deg: f64,
}
