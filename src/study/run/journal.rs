//! Journal files: a batch of finished runs saved as one binary file while a study runs, the
//! record `--resume` continues from and the results file is filled from.
//!
//! In: finished runs (id, part-file attributes, integrator name, result) and the study's
//! digest. Out: `OUT.h5.parts/batch-<first id>-<count>.journal`, written whole under
//! `….journal.tmp` and renamed (so a `kill -9` leaves either the whole batch or a `.tmp` that
//! the next run replaces), and each run read back from its place in the file.
//!
//! Layout, integers little-endian: the 16-byte tag `rotorsweep-jrnl1`, then frames. A frame
//! is its payload's length (u64), the payload's SHA-256 (32 bytes) and the payload. The first
//! frame holds the header (tool version, study digest, study inputs, number of runs), each
//! further frame one run: (id, attributes, integrator, result), postcard-encoded through serde
//! (floats as their 8 bytes, so a run read back is bit-identical to the one saved). A file
//! whose tag, checksums or run count do not hold is not read: one cut short by a crash of the
//! machine, or not rotorsweep's.
//!
//! Why not HDF5, as the results: the journal is written once and read only after an
//! interruption, so it needs no layout a reader can browse. Writing each batch of runs as an
//! HDF5 part file and copying it into the results file (`H5Ocopy`, then its dimension scales
//! re-attached) cost 25 % of a Jeffcott study's CPU, all on the one writer thread under HDF5's
//! global lock; this file costs the encoding and one `write`, and the results file is
//! written once, from the runs in memory (docs/benchmarks.md).

use std::io::{Read, Seek, SeekFrom, Write};
use std::path::Path;

use sha2::{Digest, Sha256};

use crate::dynamics::simulation::JobResult;
use crate::store::Param;

/// The file name ending of a journal.
pub(super) const EXTENSION: &str = ".journal";
/// The tag a journal starts with (format 1).
const TAG: &[u8; 16] = b"rotorsweep-jrnl1";
/// Bytes before a frame's payload: its length and its SHA-256.
const FRAME_HEAD: usize = 8 + 32;
/// A frame longer than this is not one of ours (a batch holds at most a few hundred MB).
const MAX_FRAME: u64 = 1 << 34;

/// What a journal says about itself.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
pub(super) struct Header {
    /// The version of rotorsweep that wrote it.
    pub(super) tool_version: String,
    /// The study's digest (`Identity::digest`).
    pub(super) study_digest: String,
    /// The study's inputs (`Identity::inputs_text`).
    pub(super) study_inputs: String,
    /// How many runs follow.
    pub(super) runs: u64,
}

/// One saved run, as read back.
pub(super) struct Run {
    pub(super) id: String,
    pub(super) params: Vec<(String, Param)>,
    pub(super) integrator: String,
    pub(super) result: JobResult,
}

/// Where a run is in its journal: the byte offset and length of its frame's payload.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Place {
    pub(super) offset: u64,
    pub(super) len: u64,
}

/// A run to save: its id, attributes, integrator name and result.
pub(super) type Entry<'a> = (&'a str, &'a [(String, Param)], &'a str, &'a JobResult);

/// Appends one frame holding `payload`.
fn frame(buf: &mut Vec<u8>, payload: &[u8]) {
    buf.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    buf.extend_from_slice(&Sha256::digest(payload));
    buf.extend_from_slice(payload);
}

/// Encodes a batch: the whole file's bytes and each run's place in it.
pub(super) fn encode(header: &Header, runs: &[Entry]) -> Result<(Vec<u8>, Vec<Place>), String> {
    let mut buf = Vec::with_capacity(4096);
    buf.extend_from_slice(TAG);
    let head = postcard::to_stdvec(header).map_err(|e| e.to_string())?;
    frame(&mut buf, &head);
    let mut places = Vec::with_capacity(runs.len());
    for run in runs {
        let payload = postcard::to_stdvec(run).map_err(|e| e.to_string())?;
        places.push(Place {
            offset: (buf.len() + FRAME_HEAD) as u64,
            len: payload.len() as u64,
        });
        frame(&mut buf, &payload);
    }
    Ok((buf, places))
}

/// Writes the encoded batch `bytes` to `tmp`, then renames it to `path`.
pub(super) fn write(tmp: &Path, path: &Path, bytes: &[u8]) -> Result<(), (std::io::Error, bool)> {
    let mut f = std::fs::File::create(tmp).map_err(|e| (e, false))?;
    f.write_all(bytes).map_err(|e| (e, false))?;
    drop(f);
    std::fs::rename(tmp, path).map_err(|e| (e, true))
}

/// Whether a file is a leftover of a journal's writing: empty (a write killed at its start) or
/// tagged.
pub(super) fn is_own_leftover(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| m.len() == 0) || has_tag(path)
}

/// Whether a file starts with the journal's tag.
pub(super) fn has_tag(path: &Path) -> bool {
    let mut head = [0u8; 16];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok_and(|()| &head == TAG)
}

/// The payload of the frame at `at` in `bytes`, checked; and where the next frame starts.
fn payload_at(bytes: &[u8], at: usize) -> Result<(&[u8], usize), String> {
    let head = bytes
        .get(at..at + FRAME_HEAD)
        .ok_or_else(|| format!("ends inside a frame at byte {at}"))?;
    let len = u64::from_le_bytes(head[..8].try_into().expect("8 bytes"));
    if len > MAX_FRAME {
        return Err(format!("has a frame of {len} bytes at byte {at}"));
    }
    let start = at + FRAME_HEAD;
    let payload = bytes
        .get(start..start + len as usize)
        .ok_or_else(|| format!("ends inside the frame at byte {at}"))?;
    if Sha256::digest(payload).as_slice() != &head[8..] {
        return Err(format!("has a damaged frame at byte {at} (checksum)"));
    }
    Ok((payload, start + len as usize))
}

/// Reads a journal's header and each run's id and place, checking every frame.
pub(super) fn read_index(path: &Path) -> Result<(Header, Vec<(String, Place)>), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot be read ({e})"))?;
    if bytes.get(..TAG.len()) != Some(TAG.as_slice()) {
        return Err("does not start with a rotorsweep journal's tag".into());
    }
    let (head, mut at) = payload_at(&bytes, TAG.len())?;
    let header: Header =
        postcard::from_bytes(head).map_err(|e| format!("has an unreadable header ({e})"))?;
    let mut runs = Vec::new();
    while at < bytes.len() {
        let (payload, next) = payload_at(&bytes, at)?;
        let (id, _) = postcard::take_from_bytes::<String>(payload)
            .map_err(|e| format!("has an unreadable run at byte {at} ({e})"))?;
        runs.push((
            id,
            Place {
                offset: (at + FRAME_HEAD) as u64,
                len: payload.len() as u64,
            },
        ));
        at = next;
    }
    if runs.len() as u64 != header.runs {
        return Err(format!(
            "holds {} runs where its header says {}",
            runs.len(),
            header.runs
        ));
    }
    Ok((header, runs))
}

/// Reads the run at `place` of the open journal `f`, checking its checksum.
pub(super) fn read_run(f: &mut std::fs::File, place: Place) -> Result<Run, String> {
    if place.offset < FRAME_HEAD as u64 || place.len > MAX_FRAME {
        return Err(format!("has no run at byte {}", place.offset));
    }
    let mut buf = vec![0u8; FRAME_HEAD + place.len as usize];
    f.seek(SeekFrom::Start(place.offset - FRAME_HEAD as u64))
        .and_then(|_| f.read_exact(&mut buf))
        .map_err(|e| format!("cannot be read at byte {} ({e})", place.offset))?;
    let (payload, _) = payload_at(&buf, 0)?;
    let (id, params, integrator, result) = postcard::from_bytes(payload)
        .map_err(|e| format!("has an unreadable run at byte {} ({e})", place.offset))?;
    Ok(Run {
        id,
        params,
        integrator,
        result,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::simulation::{Channel, Field};
    use crate::integrators::{Stats, Status};

    /// A result with every kind of value: NaN and signed zero (bits kept), an absent lift-off,
    /// a channel and a field with units.
    fn result() -> JobResult {
        let mut stats: Stats = serde_json::from_str(
            r#"{"status":"diverged","cause":"non-finite state","t_end_s":0.25,"steps":7,
            "rejected_error":1,"rejected_convergence":2,"newton_iterations":30,
            "jacobian_evals":3,"factorizations":4,"rhs_evals":50,"events":0,
            "cpu_time_s":0.001,"wall_time_s":0.002}"#,
        )
        .unwrap();
        stats.t_end_s = -0.0;
        JobResult {
            stats,
            modes: "3n+2st".into(),
            coordinates: 5,
            time: vec![0.0, 0.5, f64::NAN],
            channels: vec![Channel {
                name: "runout/disk/vertical".into(),
                units: "um",
                data: vec![1.0, -2.5e-300, f64::INFINITY],
            }],
            lift_off_s: None,
            fields: vec![Field {
                name: "nips/main/force".into(),
                units: "N",
                axis: "z_mm",
                axis_values: vec![10.0],
                axis_units: "mm",
                data: vec![1.0, 2.0, 3.0],
            }],
        }
    }

    fn header(runs: u64) -> Header {
        Header {
            tool_version: "0".into(),
            study_digest: "abc".into(),
            study_inputs: "[]".into(),
            runs,
        }
    }

    #[test]
    fn a_run_reads_back_bit_identical() {
        let r = result();
        let params = vec![
            ("speed.hz".to_string(), Param::Number(12.5)),
            ("label".to_string(), Param::Text("a".into())),
            ("index".to_string(), Param::Count(3)),
        ];
        let (bytes, places) = encode(&header(1), &[("j1", &params, "bdf", &r)]).unwrap();
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("b.journal");
        write(&d.path().join("b.journal.tmp"), &p, &bytes).unwrap();
        let (h, runs) = read_index(&p).unwrap();
        assert_eq!((h.study_digest.as_str(), h.runs), ("abc", 1));
        assert_eq!(runs, vec![("j1".to_string(), places[0])]);
        let back = read_run(&mut std::fs::File::open(&p).unwrap(), places[0]).unwrap();
        assert_eq!((back.id.as_str(), back.integrator.as_str()), ("j1", "bdf"));
        assert_eq!(back.params, params);
        assert_eq!(back.result.stats.status, Status::Diverged);
        assert_eq!(back.result.stats.t_end_s.to_bits(), (-0.0f64).to_bits());
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back.result.time), bits(&r.time));
        assert_eq!(back.result.channels, r.channels);
        assert_eq!(back.result.fields, r.fields);
        assert_eq!(back.result.lift_off_s, None);
    }

    #[test]
    fn a_cut_or_damaged_journal_is_not_read() {
        let r = result();
        let (bytes, _) =
            encode(&header(2), &[("a", &[], "bdf", &r), ("b", &[], "bdf", &r)]).unwrap();
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("b.journal");
        // Cut inside the second run's frame, cut after the first run, one byte flipped, another
        // tag, and a header that promises more runs than follow.
        let cut = bytes.len() - 10;
        let one = {
            let (_, places) = read_index_bytes(&bytes);
            (places[1].offset as usize) - FRAME_HEAD
        };
        let mut flipped = bytes.clone();
        flipped[cut] ^= 1;
        let mut other = bytes.clone();
        other[0] = b'R';
        for (bad, why) in [
            (&bytes[..cut], "ends inside the frame"),
            (&bytes[..one], "holds 1 runs where its header says 2"),
            (&flipped[..], "checksum"),
            (&other[..], "tag"),
        ] {
            std::fs::write(&p, bad).unwrap();
            let e = read_index(&p).unwrap_err();
            assert!(e.contains(why), "{e}");
        }
    }

    fn read_index_bytes(bytes: &[u8]) -> (Header, Vec<Place>) {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("x.journal");
        std::fs::write(&p, bytes).unwrap();
        let (h, runs) = read_index(&p).unwrap();
        (h, runs.into_iter().map(|r| r.1).collect())
    }
}
