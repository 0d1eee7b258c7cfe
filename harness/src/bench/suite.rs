//! What the record-keeping suites (`bench --suite accuracy` and `--suite models`) share:
//! their options and the `--resume` cache of each run's `record.json`.

use serde_json::Value;
use std::path::Path;

/// How a record-keeping suite runs.
pub struct SuiteOptions<'a> {
    pub scenes: &'a Path,
    pub out: &'a Path,
    /// Only the coarsest level of each case, for a few steps (smoke run).
    pub quick: bool,
    pub report: Option<&'a Path>,
    /// Only these cases (all when empty).
    pub cases: &'a [String],
    /// `--suite models`: only these soil models and levels (all when empty). With
    /// `--resume` the report still holds the recorded runs outside the selection.
    pub models: &'a [String],
    pub levels: &'a [String],
    /// Reuse a run's `record.json` under `out` when it was made with the same overrides
    /// (and model), so that an interrupted suite continues where it stopped.
    pub resume: bool,
}

impl SuiteOptions<'_> {
    /// The record at `path` when `--resume` is on and its `field` equals `key`: the run
    /// it describes was made with the same inputs and need not be repeated. An absent,
    /// unreadable or different record gives `None`, and the run is made again.
    pub fn cached(&self, path: &Path, field: &str, key: &Value) -> Option<Value> {
        if !self.resume {
            return None;
        }
        let text = std::fs::read_to_string(path).ok()?;
        serde_json::from_str::<Value>(&text)
            .ok()
            .filter(|r| &r[field] == key)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_record_is_reused_only_under_resume_and_with_the_same_key() {
        let dir = std::env::temp_dir().join(format!("granmix-suite-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("record.json");
        std::fs::write(&path, json!({"key": ["a=1"], "value": 2.0}).to_string()).unwrap();
        let mut o = SuiteOptions {
            scenes: &dir,
            out: &dir,
            quick: false,
            report: None,
            cases: &[],
            models: &[],
            levels: &[],
            resume: false,
        };
        assert!(o.cached(&path, "key", &json!(["a=1"])).is_none());
        o.resume = true;
        assert_eq!(
            o.cached(&path, "key", &json!(["a=1"])).unwrap()["value"],
            2.0
        );
        assert!(o.cached(&path, "key", &json!(["a=2"])).is_none());
        assert!(o
            .cached(&dir.join("absent.json"), "key", &json!(["a=1"]))
            .is_none());
        std::fs::remove_dir_all(&dir).ok();
    }
}
