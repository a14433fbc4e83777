//! The accuracy selection's journal of finished runs (`DIR/accuracy_runs.jsonl`).

use super::*;

/// One finished selection run as a line of the journal: its key and its record.
#[derive(Debug, Serialize, Deserialize)]
struct JournalRun {
    key: String,
    #[serde(flatten)]
    run: AccuracyRun,
}

/// The selection's journal (`DIR/accuracy_runs.jsonl`, one JSON line per finished run): a
/// selection that stops part way keeps its finished runs, and a later one with the same key
/// (the problem file and the build that ran it) reuses them, for any target.
pub struct Journal {
    pub(super) path: PathBuf,
    key: String,
    /// The runs of this key.
    runs: Vec<AccuracyRun>,
}

/// The journal's file name in a run directory.
pub const JOURNAL_FILE: &str = "accuracy_runs.jsonl";

impl Journal {
    /// The journal at `path` for runs of `key`: its lines of that key (lines of other keys
    /// stay in the file and are not used; unreadable lines are skipped).
    pub fn open(path: &Path, key: &str) -> Self {
        let runs = std::fs::read_to_string(path)
            .map(|text| {
                text.lines()
                    .filter_map(|l| serde_json::from_str::<JournalRun>(l).ok())
                    .filter(|r| r.key == key)
                    .map(|r| r.run)
                    .collect()
            })
            .unwrap_or_default();
        Journal {
            path: path.to_path_buf(),
            key: key.to_string(),
            runs,
        }
    }

    /// The key of a problem file's runs by one build: FNV-1a hashes of the file's text and
    /// of the build's identity (the command line passes its executable's bytes), so a
    /// changed file or a rebuilt program never reuses a run.
    pub fn key(problem_text: &str, build: &[u8]) -> String {
        format!(
            "{:016x}-{:016x}",
            crate::studies::fnv1a(problem_text.as_bytes()),
            crate::studies::fnv1a(build)
        )
    }

    /// The runs of this key read back.
    pub fn len(&self) -> usize {
        self.runs.len()
    }

    /// Whether no run of this key was read back.
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    pub(super) fn find(&self, elements: usize, res: Resolution) -> Option<&AccuracyRun> {
        self.runs.iter().find(|r| {
            r.elements == elements
                && Resolution::from_parts(r.dt, r.error_tolerance).is_some_and(|x| x.same(res))
        })
    }

    /// Append a finished run (a warning, not a failure, when the file cannot be written).
    pub(super) fn append(&mut self, run: &AccuracyRun) {
        let line = JournalRun {
            key: self.key.clone(),
            run: run.clone(),
        };
        let text = serde_json::to_string(&line).expect("a journal line serialises");
        let written = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&self.path)
            .and_then(|mut f| writeln!(f, "{text}"));
        if let Err(e) = written {
            log::warn!("{}: cannot append a run: {e}", self.path.display());
        }
        self.runs.push(line.run);
    }
}
