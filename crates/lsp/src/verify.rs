//! Verification in the editor: the `robosim.verify` command, its code
//! lenses, and the results.
//!
//! A run is a background job on a thread of its own, on a snapshot of the
//! database. The engine's search runs no salsa query, so salsa cannot
//! cancel it; and a write to the database waits for every snapshot to be
//! dropped. So every write first stops the running jobs through their
//! budget's cancellation flag (under the state lock, before the write):
//! the engine returns within milliseconds and the job drops its snapshot
//! before it takes any lock. A change to the text of any file also makes
//! the results stale: they are dropped and their diagnostics cleared. A
//! job's result is kept only if the job was not cancelled and nothing
//! changed since it started.
//!
//! While a job runs, `$/progress` reports the states explored (when the
//! client supports work-done progress), and `window/workDoneProgress/cancel`
//! stops it. A new request for the same target stops the one running.

use std::collections::{BTreeSet, HashMap};
use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use robosim_ide::verify::{
    format_seconds, lens_title, overall_verdict, AsyncBuffer, Budget, Options, Profile, Report, Stats,
};
use robosim_ide::{Verified, VerifyLens, VerifyTarget};
use serde_json::{json, Value};
use tokio::sync::mpsc::{unbounded_channel, UnboundedReceiver, UnboundedSender};
use tower_lsp_server::jsonrpc::{Error, ErrorCode, Result};
use tower_lsp_server::ls_types::{
    notification, ExecuteCommandParams, MessageType, NumberOrString, ProgressParams, ProgressParamsValue, Uri,
    WorkDoneProgress, WorkDoneProgressBegin, WorkDoneProgressEnd, WorkDoneProgressReport,
};
use tower_lsp_server::Client;

use crate::diagnostics;
use crate::state::{key_of, Shared};

/// The command that runs a check.
pub(crate) const COMMAND: &str = "robosim.verify";

/// How often progress is reported while a check runs.
const PROGRESS_PERIOD: Duration = Duration::from_millis(200);

/// The `robosim.verify.*` settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct VerifySettings {
    /// `robosim.verify.semantics`.
    pub(crate) profile: Profile,
    /// `robosim.verify.timeoutSeconds`.
    pub(crate) timeout: Duration,
    /// `robosim.verify.asyncBuffer` (`"1:overwrite"`; `""` for none).
    pub(crate) async_buffer: Option<AsyncBuffer>,
}

impl Default for VerifySettings {
    fn default() -> Self {
        VerifySettings { profile: Profile::RoboTool3, timeout: Duration::from_secs(60), async_buffer: None }
    }
}

#[derive(Debug)]
struct Job {
    id: u64,
    cancel: Arc<AtomicBool>,
    token: Option<NumberOrString>,
}

#[derive(Debug)]
struct Run {
    id: u64,
    profile: Profile,
    reports: Vec<Report>,
}

/// What a started job needs to know.
pub(crate) struct Started {
    id: u64,
    cancel: Arc<AtomicBool>,
    generation: u64,
    token: Option<NumberOrString>,
    profile: Profile,
}

/// Running jobs and the results of finished ones (in the state, under its
/// lock).
#[derive(Debug, Default)]
pub(crate) struct Verification {
    pub(crate) settings: VerifySettings,
    jobs: HashMap<VerifyTarget, Job>,
    runs: HashMap<VerifyTarget, Run>,
    next_id: u64,
    /// Bumped by every change of the workspace's text.
    generation: u64,
    /// Per file key, bumped whenever the file's verification diagnostics
    /// change: a publish computed with an older stamp is not sent.
    stamps: HashMap<String, u64>,
    /// Whether the lenses changed since the client was last told.
    lenses_changed: bool,
}

impl Verification {
    /// Stops every running job (before a write to the database, which
    /// waits for their snapshots).
    pub(crate) fn cancel_all(&self) {
        for job in self.jobs.values() {
            job.cancel.store(true, Ordering::SeqCst);
        }
    }

    /// The text of the workspace changed: running jobs stop and results
    /// are dropped.
    pub(crate) fn invalidate(&mut self) {
        self.cancel_all();
        self.generation += 1;
        if self.runs.is_empty() && self.jobs.is_empty() {
            return;
        }
        let files: BTreeSet<String> =
            self.runs.values().flat_map(|r| r.reports.iter().map(|r| r.file.clone())).collect();
        self.runs.clear();
        for f in files {
            self.bump(f);
        }
        self.lenses_changed = true;
    }

    fn bump(&mut self, key: String) {
        self.next_id += 1;
        self.stamps.insert(key, self.next_id);
    }

    /// The stamp of the verification diagnostics of `key`.
    pub(crate) fn stamp(&self, key: &str) -> u64 {
        self.stamps.get(key).copied().unwrap_or(0)
    }

    /// Whether the lenses changed since the last call.
    pub(crate) fn take_lenses_changed(&mut self) -> bool {
        std::mem::take(&mut self.lenses_changed)
    }

    /// Registers a job for `target`, stopping the one running for it.
    fn start(&mut self, target: &VerifyTarget, client_token: Option<NumberOrString>, progress: bool) -> Started {
        if let Some(old) = self.jobs.get(target) {
            old.cancel.store(true, Ordering::SeqCst);
        }
        self.next_id += 1;
        let id = self.next_id;
        let token = match client_token {
            Some(t) => Some(t),
            None if progress => Some(NumberOrString::String(format!("robosim/verify/{id}"))),
            None => None,
        };
        let cancel = Arc::new(AtomicBool::new(false));
        self.jobs.insert(target.clone(), Job { id, cancel: cancel.clone(), token: token.clone() });
        self.lenses_changed = true;
        Started { id, cancel, generation: self.generation, token, profile: self.settings.profile }
    }

    /// A job ended. Its reports are kept if it was not cancelled and the
    /// text did not change since it started: then returns the files whose
    /// verification diagnostics change.
    fn finish(&mut self, target: &VerifyTarget, job: &Started, result: Option<Vec<Report>>) -> Option<Vec<String>> {
        if self.jobs.get(target).is_some_and(|j| j.id == job.id) {
            self.jobs.remove(target);
            self.lenses_changed = true;
        }
        if job.cancel.load(Ordering::SeqCst) || job.generation != self.generation {
            return None;
        }
        let reports = result?;
        let mut files: BTreeSet<String> = reports.iter().map(|r| r.file.clone()).collect();
        let run = Run { id: job.id, profile: job.profile, reports };
        if let Some(old) = self.runs.insert(target.clone(), run) {
            files.extend(old.reports.iter().map(|r| r.file.clone()));
        }
        for f in &files {
            self.bump(f.clone());
        }
        self.lenses_changed = true;
        Some(files.into_iter().collect())
    }

    /// Stops the job that reports progress under `token`.
    pub(crate) fn cancel_token(&self, token: &NumberOrString) -> bool {
        let job = self.jobs.values().find(|j| j.token.as_ref() == Some(token));
        if let Some(j) = job {
            j.cancel.store(true, Ordering::SeqCst);
        }
        job.is_some()
    }

    /// The counterexamples of the last runs (for drawing them on diagrams).
    pub(crate) fn counterexamples(&self) -> Vec<robosim_ide::verify::Counterexample> {
        let mut runs: Vec<&Run> = self.runs.values().collect();
        runs.sort_by_key(|r| r.id);
        runs.iter().flat_map(|r| r.reports.iter().filter_map(|r| r.counterexample.clone())).collect()
    }

    /// The last report about each assertion of the file `key` (by the
    /// assertion's name range), in the order the runs started.
    pub(crate) fn reports_for(&self, key: &str) -> Vec<Verified> {
        let mut runs: Vec<&Run> = self.runs.values().collect();
        runs.sort_by_key(|r| r.id);
        let mut out: Vec<Verified> = Vec::new();
        for run in runs {
            // A run replaces every earlier report on the assertions it
            // checked (RT-8: one per semantics, so several per assertion).
            let mine: Vec<&Report> = run.reports.iter().filter(|r| r.file == key).collect();
            out.retain(|v| !mine.iter().any(|r| r.name_range == v.report.name_range));
            out.extend(mine.into_iter().map(|r| Verified { report: r.clone(), profile: run.profile }));
        }
        out
    }

    /// A lens's title: what it runs, the last verdict, or that it is
    /// running.
    pub(crate) fn lens_title(&self, lens: &VerifyLens) -> String {
        let running = self.jobs.contains_key(&lens.target);
        match lens.assertion_range {
            Some(range) => {
                let all = self.reports_for(lens.target.path());
                let mine: Vec<&Report> =
                    all.iter().filter(|v| v.report.name_range == range).map(|v| &v.report).collect();
                lens_title(lens, &mine, running)
            }
            None => {
                let reports: Vec<&Report> =
                    self.runs.get(&lens.target).map(|r| r.reports.iter().collect()).unwrap_or_default();
                lens_title(lens, &reports, running)
            }
        }
    }
}

/// The command's arguments for a target: `[uri, name]` for an assertion,
/// `[uri, {"simulation": name}]` for a simulation's schedulability.
pub(crate) fn arguments(uri: &Uri, target: &VerifyTarget) -> Vec<Value> {
    let what = match target {
        VerifyTarget::Assertion { name, .. } => json!(name),
        VerifyTarget::Simulation { name, .. } => json!({ "simulation": name }),
    };
    vec![json!(uri.as_str()), what]
}

fn parse_arguments(args: &[Value]) -> std::result::Result<VerifyTarget, String> {
    const USAGE: &str = "`robosim.verify` takes [uri, assertion name] or [uri, {\"simulation\": name}]";
    let [uri, what] = args else { return Err(USAGE.to_string()) };
    let uri: Uri = uri.as_str().and_then(|u| u.parse().ok()).ok_or_else(|| USAGE.to_string())?;
    let path = key_of(&uri);
    match what {
        Value::String(name) => Ok(VerifyTarget::Assertion { path, name: name.clone() }),
        Value::Object(o) => match o.get("simulation").and_then(Value::as_str) {
            Some(name) => Ok(VerifyTarget::Simulation { path, name: name.to_string() }),
            None => Err(USAGE.to_string()),
        },
        _ => Err(USAGE.to_string()),
    }
}

fn invalid_params(message: String) -> Error {
    Error { code: ErrorCode::InvalidParams, message: message.into(), data: None }
}

/// `workspace/executeCommand`: checks the arguments, starts the job and
/// answers at once (`null`); the results come as diagnostics, lens titles
/// and hovers.
pub(crate) async fn execute(shared: &Arc<Shared>, params: ExecuteCommandParams) -> Result<Option<Value>> {
    if params.command != COMMAND {
        return Err(invalid_params(format!("unknown command `{}`", params.command)));
    }
    let target = parse_arguments(&params.arguments).map_err(invalid_params)?;
    for _ in 0..3 {
        let analysis = {
            let st = shared.lock();
            if st.files.get(target.path()).and_then(|e| e.file).is_none() {
                return Err(invalid_params(format!("`{}` is not a file of the workspace", target.path())));
            }
            st.host.analysis()
        };
        let t = target.clone();
        match tokio::task::spawn_blocking(move || analysis.check_verify_target(&t)).await {
            Ok(Ok(Ok(()))) => {
                start(shared, target, params.work_done_progress_params.work_done_token);
                return Ok(None);
            }
            Ok(Ok(Err(message))) => return Err(invalid_params(message)),
            Ok(Err(_cancelled)) => continue,
            Err(e) => {
                return Err(Error {
                    code: ErrorCode::InternalError,
                    message: format!("the request failed: {e}").into(),
                    data: None,
                })
            }
        }
    }
    Err(Error::content_modified())
}

enum ProgressMsg {
    Report(String),
    End(String),
}

fn stats_message(s: &Stats) -> String {
    format!("{} states, {} transitions, ply {} · {}", s.states, s.transitions, s.plies, format_seconds(s.seconds))
}

/// What a finished run says in its progress end and the log.
fn summary(reports: &[Report]) -> String {
    let verdict = overall_verdict(reports).map_or("no assertion", |v| v.name());
    let states: u64 = reports.iter().map(|r| r.stats.states).sum();
    let seconds: f64 = reports.iter().map(|r| r.stats.seconds).sum();
    let mut s = format!("{verdict} · {states} states · {}", format_seconds(seconds));
    // RT-8: a plain assertion has a report per semantics.
    let mut assertions: Vec<(&str, _)> = reports.iter().map(|r| (r.file.as_str(), r.name_range.start())).collect();
    assertions.dedup();
    if assertions.len() < reports.len() {
        s.push_str(&format!(" ({} assertions, {} analyses)", assertions.len(), reports.len()));
    } else if reports.len() > 1 {
        s.push_str(&format!(" ({} assertions)", reports.len()));
    }
    s
}

/// Starts the job for `target`.
fn start(shared: &Arc<Shared>, target: VerifyTarget, client_token: Option<NumberOrString>) {
    let Some(client) = shared.client().cloned() else { return };
    let (analysis, job, opts, supports_progress) = {
        let mut st = shared.lock();
        let supports_progress = st.caps.work_done_progress;
        let job = st.verify.start(&target, client_token.clone(), supports_progress);
        let settings = st.verify.settings;
        // One core stays free for the editor's other requests.
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).saturating_sub(1).max(1);
        let budget = Budget {
            timeout: Some(settings.timeout),
            cancel: Some(job.cancel.clone()),
            ..Budget::default().with_threads(threads)
        };
        (
            st.host.analysis(),
            job,
            Options { profile: settings.profile, budget, async_buffer: settings.async_buffer },
            supports_progress,
        )
    };
    let (tx, rx) = unbounded_channel();
    if let Some(token) = job.token.clone() {
        let create = client_token.is_none() && supports_progress;
        let title = format!("Verifying {}", target.describe());
        shared.runtime.spawn(progress_task(client.clone(), token, create, title, rx));
    }
    refresh_lenses(shared);
    let worker = shared.clone();
    let spawned = std::thread::Builder::new()
        .name("robosim-verify".into())
        // As the runtime's threads: analyses recurse over syntax trees.
        .stack_size(16 << 20)
        .spawn(move || {
            // Background work, as checks are; the search's own threads
            // inherit the priority.
            crate::background::lower_priority(worker.background_nice);
            run_job(&worker, analysis, target, job, opts, tx)
        });
    if let Err(e) = spawned {
        shared.log(MessageType::ERROR, format!("cannot start a verification thread: {e}"));
    }
}

fn run_job(
    shared: &Arc<Shared>,
    analysis: robosim_ide::Analysis,
    target: VerifyTarget,
    job: Started,
    opts: Options,
    tx: UnboundedSender<ProgressMsg>,
) {
    let last = Mutex::new(Instant::now());
    let progress = |s: &Stats| {
        let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
        if last.elapsed() >= PROGRESS_PERIOD {
            *last = Instant::now();
            let _ = tx.send(ProgressMsg::Report(stats_message(s)));
        }
    };
    let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| analysis.verify(&target, &opts, Some(&progress))));
    // Before any lock: a write waiting for this snapshot may hold it.
    drop(analysis);
    let (reports, failure) = match outcome {
        Ok(Ok(Ok(reports))) => (Some(reports), None),
        Ok(Ok(Err(message))) => (None, Some(message)),
        // A write cancelled a query: the job was cancelled too.
        Ok(Err(_cancelled)) => (None, None),
        Err(_panic) => (None, Some("the checker failed (an internal error)".to_string())),
    };
    let summary_text = reports.as_deref().map(summary);
    let affected = shared.lock().verify.finish(&target, &job, reports);
    let end = match (&affected, summary_text, &failure) {
        (Some(_), Some(s), _) => s,
        (_, _, Some(f)) => f.clone(),
        _ => "cancelled".to_string(),
    };
    let _ = tx.send(ProgressMsg::End(end.clone()));
    match (&affected, failure) {
        (Some(files), _) => {
            shared.log(MessageType::INFO, format!("{}: {end}", target.describe()));
            diagnostics::republish(shared, files.clone());
        }
        (None, Some(f)) => shared.log(MessageType::ERROR, format!("{}: {f}", target.describe())),
        (None, None) => shared.log(MessageType::INFO, format!("{}: cancelled", target.describe())),
    }
    refresh_lenses(shared);
}

/// Sends a job's `$/progress` notifications in order: begin, reports, end.
async fn progress_task(
    client: Client,
    token: NumberOrString,
    create: bool,
    title: String,
    mut rx: UnboundedReceiver<ProgressMsg>,
) {
    if create && client.create_work_done_progress(token.clone()).await.is_err() {
        return;
    }
    let send = |value: WorkDoneProgress| {
        let client = client.clone();
        let token = token.clone();
        async move {
            client
                .send_notification::<notification::Progress>(ProgressParams {
                    token,
                    value: ProgressParamsValue::WorkDone(value),
                })
                .await
        }
    };
    send(WorkDoneProgress::Begin(WorkDoneProgressBegin {
        title,
        cancellable: Some(true),
        message: Some("starting".to_string()),
        percentage: None,
    }))
    .await;
    let mut end = "cancelled".to_string();
    while let Some(msg) = rx.recv().await {
        match msg {
            ProgressMsg::Report(message) => {
                send(WorkDoneProgress::Report(WorkDoneProgressReport {
                    cancellable: Some(true),
                    message: Some(message),
                    percentage: None,
                }))
                .await
            }
            ProgressMsg::End(message) => {
                end = message;
                break;
            }
        }
    }
    send(WorkDoneProgress::End(WorkDoneProgressEnd { message: Some(end) })).await;
}

/// Asks the client to request code lenses again, when it can and they
/// changed.
pub(crate) fn refresh_lenses(shared: &Arc<Shared>) {
    let changed = {
        let mut st = shared.lock();
        let changed = st.verify.take_lenses_changed();
        changed && st.caps.code_lens_refresh
    };
    if !changed {
        return;
    }
    if let Some(client) = shared.client().cloned() {
        shared.runtime.spawn(async move {
            let _ = client.code_lens_refresh().await;
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_round_trip() {
        let uri: Uri = "file:///w/checks.rsa".parse().unwrap();
        for target in [
            VerifyTarget::Assertion { path: "/w/checks.rsa".into(), name: "S1".into() },
            VerifyTarget::Simulation { path: "/w/checks.rsa".into(), name: "P1".into() },
        ] {
            assert_eq!(parse_arguments(&arguments(&uri, &target)), Ok(target));
        }
        assert!(parse_arguments(&[json!("file:///w/checks.rsa")]).is_err());
        assert!(parse_arguments(&[json!(1), json!("S1")]).is_err());
        assert!(parse_arguments(&[json!("file:///w/checks.rsa"), json!({"x": 1})]).is_err());
    }
}
