//! The workspace on disk: scanning the folders (with `$/progress`),
//! following file-watcher events, and the settings (`robosim.rules`,
//! `robosim.verify.semantics`, `robosim.verify.timeoutSeconds`).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use robosim_ide::verify::Profile;
use robosim_ide::workspace_files::{find_model_files, looks_like_restructured_text, read_model_file};
use robosim_ide::{FileKind, RuleSet};
use serde_json::Value;
use tower_lsp_server::ls_types::{
    self as lsp, ConfigurationItem, FileChangeType, FileSystemWatcher, GlobPattern, MessageType, NumberOrString,
    Registration,
};

use crate::diagnostics;
use crate::state::{Phase, Shared};
use crate::verify::VerifySettings;

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
/// client supports it, then checks the whole workspace. The caller began
/// a load ([`State::begin_load`](crate::state::State::begin_load)) for a
/// non-empty `roots`.
pub(crate) async fn load_roots(shared: Arc<Shared>, roots: Vec<PathBuf>) {
    if roots.is_empty() {
        return;
    }
    let Some(client) = shared.client().cloned() else {
        shared.lock().end_load();
        return;
    };
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
            // RoboTool resolves names per project (a folder with a
            // `.project`): the roots found join those already known.
            let mut projects = st.host.projects();
            projects.extend(robosim_ide::workspace_files::project_roots(
                files.iter().map(|(p, _)| std::path::Path::new(p.as_str())),
            ));
            st.host.set_projects(projects);
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
    shared.lock().end_load();
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

/// A `robosim.verify.KEY` setting from a settings object, in the same forms
/// as `robosim.rules` (and `{"verify": {KEY: …}}`, `{"verify.KEY": …}`).
fn verify_setting<'a>(settings: &'a Value, key: &str) -> Option<&'a Value> {
    let nested = |v: &'a Value| v.get("verify").and_then(|v| v.get(key)).or_else(|| v.get(format!("verify.{key}")));
    settings
        .get("robosim")
        .and_then(nested)
        .or_else(|| settings.get(format!("robosim.verify.{key}")))
        .or_else(|| nested(settings))
        .filter(|v| !v.is_null())
}

/// The verification settings of a settings object, over `current`:
/// `None` when it has none; the messages of values that are not valid.
pub(crate) fn verify_from_settings(settings: &Value, current: VerifySettings) -> Option<(VerifySettings, Vec<String>)> {
    let semantics = verify_setting(settings, "semantics");
    let timeout = verify_setting(settings, "timeoutSeconds");
    let buffer = verify_setting(settings, "asyncBuffer");
    if semantics.is_none() && timeout.is_none() && buffer.is_none() {
        return None;
    }
    let mut out = current;
    let mut problems = Vec::new();
    match semantics.map(|v| (v, v.as_str())) {
        None => {}
        Some((_, Some("robotool3"))) => out.profile = Profile::RoboTool3,
        Some((_, Some("paper2019"))) => out.profile = Profile::Paper2019,
        Some((v, _)) => {
            problems.push(format!("`robosim.verify.semantics` must be \"robotool3\" or \"paper2019\", not {v}"))
        }
    }
    if let Some(v) = timeout {
        match v.as_f64() {
            Some(t) if t.is_finite() && t > 0.0 && t <= 1e9 => out.timeout = std::time::Duration::from_secs_f64(t),
            _ => problems.push(format!("`robosim.verify.timeoutSeconds` must be a positive number, not {v}")),
        }
    }
    match buffer.map(|v| (v, v.as_str().map(str::trim))) {
        None => {}
        Some((_, Some("" | "none"))) => out.async_buffer = None,
        Some((_, Some(text))) => match robosim_ide::verify::AsyncBuffer::parse(text) {
            Ok(b) => out.async_buffer = Some(b),
            Err(e) => problems.push(format!("`robosim.verify.asyncBuffer`: {e}")),
        },
        Some((v, None)) => problems.push(format!(
            "`robosim.verify.asyncBuffer` must be a string such as \"1:overwrite\" or \"2:block\", not {v}"
        )),
    }
    Some((out, problems))
}

/// Applies the verification settings found in `settings` (for the next
/// runs); returns whether there were any.
pub(crate) fn apply_verify_settings(shared: &Arc<Shared>, settings: &Value) -> bool {
    let current = shared.lock().verify.settings;
    let Some((new, problems)) = verify_from_settings(settings, current) else { return false };
    shared.lock().verify.settings = new;
    for p in problems {
        shared.log(MessageType::WARNING, p);
    }
    true
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
            // The section's value itself: `{"rules": …, "verify": {…}}`.
            if let Some(rules) = values.first().and_then(rules_from_settings) {
                apply_rules(shared, rules);
            }
            if let Some(section) = values.first() {
                apply_verify_settings(shared, section);
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

    #[test]
    fn verify_setting_forms() {
        let d = VerifySettings::default();
        assert_eq!(d.profile, Profile::RoboTool3);
        assert_eq!(d.timeout, std::time::Duration::from_secs(60));
        let paper = VerifySettings { profile: Profile::Paper2019, ..d };
        for form in [
            json!({"verify": {"semantics": "paper2019"}}),
            json!({"robosim": {"verify": {"semantics": "paper2019"}}}),
            json!({"robosim.verify.semantics": "paper2019"}),
            json!({"verify.semantics": "paper2019"}),
        ] {
            assert_eq!(verify_from_settings(&form, d), Some((paper, vec![])), "{form}");
        }
        let (s, problems) = verify_from_settings(&json!({"verify": {"timeoutSeconds": 2.5}}), paper).unwrap();
        assert_eq!(
            (s.profile, s.timeout, problems.len()),
            (Profile::Paper2019, std::time::Duration::from_millis(2500), 0)
        );
        let (s, problems) =
            verify_from_settings(&json!({"verify": {"semantics": "fdr", "timeoutSeconds": -1}}), d).unwrap();
        assert_eq!((s, problems.len()), (d, 2));
        let (s, problems) = verify_from_settings(&json!({"verify": {"asyncBuffer": "2:block"}}), d).unwrap();
        let block2 = robosim_ide::verify::AsyncBuffer { size: 2, overwrite: false };
        assert_eq!((s.async_buffer, problems.len()), (Some(block2), 0));
        let (s, problems) = verify_from_settings(&json!({"verify": {"asyncBuffer": ""}}), s).unwrap();
        assert_eq!((s.async_buffer, problems.len()), (None, 0));
        let (s, problems) = verify_from_settings(&json!({"verify": {"asyncBuffer": "0:drop"}}), d).unwrap();
        assert_eq!((s, problems.len()), (d, 1));
        assert_eq!(verify_from_settings(&json!({"rules": "paper"}), d), None);
        assert_eq!(verify_from_settings(&json!(null), d), None);
    }
}
