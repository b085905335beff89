//! The workspace on disk: scanning the folders (with `$/progress`),
//! following file-watcher events, and the `robosim.rules` setting.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use robosim_ide::workspace_files::{find_model_files, looks_like_restructured_text, read_model_file};
use robosim_ide::{FileKind, RuleSet};
use serde_json::Value;
use tower_lsp_server::ls_types::{
    self as lsp, ConfigurationItem, FileChangeType, FileSystemWatcher, GlobPattern, MessageType, NumberOrString,
    Registration,
};

use crate::diagnostics;
use crate::state::{Phase, Shared};

/// Reads the model files under `roots` (on a blocking thread: it is I/O).
fn scan(roots: &[PathBuf]) -> (Vec<(String, String)>, Vec<String>) {
    let mut files = Vec::new();
    let mut problems = Vec::new();
    for root in roots {
        let (found, errors) = find_model_files(root);
        for (dir, e) in errors {
            problems.push(format!("cannot read `{}`: {e}", dir.display()));
        }
        for path in found {
            match read_model_file(&path) {
                Ok((text, _)) => {
                    // The same rule as `robosim check` for folders.
                    if FileKind::from_path(&path) == Some(FileKind::RoboSim) && looks_like_restructured_text(&text) {
                        continue;
                    }
                    files.push((path.to_string_lossy().into_owned(), text));
                }
                Err(e) => problems.push(format!("cannot read `{}`: {e}", path.display())),
            }
        }
    }
    (files, problems)
}

/// Loads every model file under `roots`, reporting progress when the
/// client supports it, then checks the whole workspace.
pub(crate) async fn load_roots(shared: Arc<Shared>, roots: Vec<PathBuf>) {
    let Some(client) = shared.client().cloned() else { return };
    if roots.is_empty() {
        return;
    }
    let supports_progress = shared.lock().caps.work_done_progress;
    let token = NumberOrString::String(format!("robosim/load/{}", roots[0].display()));
    let progress = if supports_progress && client.create_work_done_progress(token.clone()).await.is_ok() {
        Some(client.progress(token, "robosim").with_message("Loading models").begin().await)
    } else {
        None
    };
    let worker = shared.clone();
    let loaded = tokio::task::spawn_blocking(move || {
        let (files, problems) = scan(&roots);
        let n = files.len();
        {
            let mut st = worker.lock();
            for (path, text) in files {
                st.set_disk_file(&path, text);
            }
        }
        (n, problems)
    })
    .await;
    let (n, problems) = loaded.unwrap_or_else(|e| (0, vec![format!("loading the workspace failed: {e}")]));
    for p in problems {
        shared.log(MessageType::WARNING, p);
    }
    shared.log(MessageType::INFO, format!("loaded {n} model file{}", if n == 1 { "" } else { "s" }));
    diagnostics::schedule(&shared, None, true);
    if let Some(p) = progress {
        p.finish_with_message(format!("{n} model file{}", if n == 1 { "" } else { "s" })).await;
    }
}

/// Forgets the files on disk under `root` that are not open.
pub(crate) fn unload_root(shared: &Arc<Shared>, root: &Path) {
    {
        let mut st = shared.lock();
        let keys: Vec<String> = st.files.keys().filter(|k| Path::new(k.as_str()).starts_with(root)).cloned().collect();
        for k in keys {
            st.remove_disk_file(&k);
        }
    }
    diagnostics::schedule(shared, None, true);
}

/// Reads a closed file back from disk (its buffer was closed), then checks
/// the workspace again.
pub(crate) fn reload_from_disk(shared: &Arc<Shared>, key: String) {
    let shared = shared.clone();
    let runtime = shared.runtime.clone();
    runtime.spawn_blocking(move || {
        let text = read_model_file(Path::new(&key)).map(|(t, _)| t);
        {
            let mut st = shared.lock();
            match text {
                Ok(text) => {
                    st.set_disk_file(&key, text);
                }
                Err(_) => {
                    st.remove_disk_file(&key);
                }
            }
        }
        diagnostics::schedule(&shared, None, true);
    });
}

/// Applies watcher events: created and changed files are read, deleted
/// ones removed; open documents are left to the client.
pub(crate) fn watched_files_changed(shared: &Arc<Shared>, changes: Vec<lsp::FileEvent>) {
    let shared = shared.clone();
    let runtime = shared.runtime.clone();
    runtime.spawn_blocking(move || {
        let mut changed = false;
        for change in changes {
            let key = crate::state::key_of(&change.uri);
            let path = PathBuf::from(&key);
            if !path.is_absolute() || FileKind::from_path(&path).is_none() {
                continue;
            }
            if change.typ == FileChangeType::DELETED {
                changed |= shared.lock().remove_disk_file(&key).is_some();
                continue;
            }
            match read_model_file(&path) {
                Ok((text, _)) => {
                    if FileKind::from_path(&path) == Some(FileKind::RoboSim) && looks_like_restructured_text(&text) {
                        continue;
                    }
                    changed |= shared.lock().set_disk_file(&key, text).is_some();
                }
                // Gone again by the time we looked.
                Err(_) => changed |= shared.lock().remove_disk_file(&key).is_some(),
            }
        }
        if changed {
            diagnostics::schedule(&shared, None, true);
        }
    });
}

/// Asks the client to watch model files, when it can register watchers.
pub(crate) async fn register_watchers(shared: &Arc<Shared>) {
    let Some(client) = shared.client().cloned() else { return };
    if !shared.lock().caps.watched_files_registration {
        return;
    }
    let options = lsp::DidChangeWatchedFilesRegistrationOptions {
        watchers: vec![FileSystemWatcher {
            glob_pattern: GlobPattern::String("**/*.{rct,rst,assertions,rsa}".to_string()),
            kind: None,
        }],
    };
    let registration = Registration {
        id: "robosim-watched-files".to_string(),
        method: "workspace/didChangeWatchedFiles".to_string(),
        register_options: serde_json::to_value(options).ok(),
    };
    if let Err(e) = client.register_capability(vec![registration]).await {
        shared.log(MessageType::WARNING, format!("the client refused to watch model files: {}", e.message));
    }
}

/// `paper` or `robotool` from a settings object: `{"rules": …}` under
/// `robosim`, or `{"robosim": {"rules": …}}`, or `{"robosim.rules": …}`.
pub(crate) fn rules_from_settings(settings: &Value) -> Option<Result<RuleSet, String>> {
    let value = settings
        .get("robosim")
        .and_then(|r| r.get("rules"))
        .or_else(|| settings.get("robosim.rules"))
        .or_else(|| settings.get("rules"))?;
    Some(match value.as_str() {
        Some("paper") => Ok(RuleSet::Paper),
        Some("robotool") => Ok(RuleSet::RoboTool),
        _ => Err(format!("`robosim.rules` must be \"paper\" or \"robotool\", not {value}")),
    })
}

/// Applies a rule set; re-checks everything when it changed.
pub(crate) fn apply_rules(shared: &Arc<Shared>, rules: Result<RuleSet, String>) {
    match rules {
        Ok(rules) => {
            let shared2 = shared.clone();
            let runtime = shared.runtime.clone();
            // A write to the database: on a blocking thread, since it waits
            // for running queries to unwind.
            runtime.spawn_blocking(move || {
                if shared2.phase() != Phase::Running {
                    return;
                }
                let changed = shared2.lock().set_rules(rules);
                if changed {
                    diagnostics::schedule(&shared2, None, true);
                }
            });
        }
        Err(msg) => shared.log(MessageType::WARNING, msg),
    }
}

/// Pulls `robosim` settings with `workspace/configuration`, when supported.
pub(crate) async fn pull_configuration(shared: &Arc<Shared>) {
    let Some(client) = shared.client().cloned() else { return };
    if !shared.lock().caps.configuration {
        return;
    }
    let item = ConfigurationItem { scope_uri: None, section: Some("robosim".to_string()) };
    match client.configuration(vec![item]).await {
        Ok(values) => {
            // The section's value itself: `{"rules": …}`.
            if let Some(rules) = values.first().and_then(rules_from_settings) {
                apply_rules(shared, rules);
            }
        }
        Err(e) => shared.log(MessageType::WARNING, format!("could not read the `robosim` settings: {}", e.message)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn rules_setting_forms() {
        assert_eq!(rules_from_settings(&json!({"rules": "robotool"})), Some(Ok(RuleSet::RoboTool)));
        assert_eq!(rules_from_settings(&json!({"robosim": {"rules": "paper"}})), Some(Ok(RuleSet::Paper)));
        assert_eq!(rules_from_settings(&json!({"robosim.rules": "robotool"})), Some(Ok(RuleSet::RoboTool)));
        assert!(matches!(rules_from_settings(&json!({"rules": 3})), Some(Err(_))));
        assert_eq!(rules_from_settings(&json!({"other": 1})), None);
        assert_eq!(rules_from_settings(&json!(null)), None);
    }
}
