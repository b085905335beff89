//! The server's state: the analysis host, what the client has open (text
//! and version), what was found on disk, and the client's capabilities.
//! One `std::sync::Mutex` guards it; it is held only for short, synchronous
//! sections and never across an `.await`.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};

use robosim_ide::{AnalysisHost, Durability, Edit, FileId, FileKind, LineIndex, RuleSet, TextRange, TextSize};
use tower_lsp_server::ls_types::{self as lsp, MessageType, Uri};
use tower_lsp_server::Client;

use crate::convert::Text;

/// Everything the handlers share.
pub(crate) struct Shared {
    state: Mutex<State>,
    client: OnceLock<Client>,
    /// Held while a `publishDiagnostics` is checked and sent, so that two
    /// publishes for one document cannot overtake each other on the wire.
    pub(crate) publish: Mutex<()>,
    phase: AtomicU8,
    /// Whether `shutdown` was received: the exit code depends on it.
    pub(crate) shutdown_requested: AtomicBool,
    /// The runtime, for work started from blocking threads.
    pub(crate) runtime: tokio::runtime::Handle,
    /// The priority (nice value) of background threads: one level below
    /// the server's, fixed at start so that background threads started by
    /// background threads do not sink further.
    pub(crate) background_nice: Option<i32>,
    /// How long after an edit the syntax-only publish waits for the
    /// complete check (`diagnostics.rs`; none by default): when the check
    /// is done by then, only its publish goes out.
    pub(crate) syntax_hold: std::time::Duration,
}

/// Where the server is in the protocol's life cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Phase {
    /// Before a successful `initialize`: notifications are dropped.
    Uninitialized = 0,
    /// Serving.
    Running = 1,
    /// After `shutdown`: only `exit` matters.
    ShutDown = 2,
}

/// The syntax-only publish's wait for the complete check:
/// `ROBOSIM_SYNTAX_HOLD_MS`, by default none. A wait shorter than the
/// check (about 3 ms after a keystroke in a 10,000-line file on an idle
/// machine) only delays the syntax errors; a longer one makes the complete
/// publish the first, and usually the only one, at the cost of a later
/// first publish: for measuring either way.
fn syntax_hold() -> std::time::Duration {
    let ms = std::env::var("ROBOSIM_SYNTAX_HOLD_MS").ok().and_then(|v| v.trim().parse::<f64>().ok());
    std::time::Duration::from_secs_f64(ms.unwrap_or(0.0).clamp(0.0, 10_000.0) / 1e3)
}

impl Shared {
    pub(crate) fn new(runtime: tokio::runtime::Handle) -> Arc<Shared> {
        Arc::new(Shared {
            state: Mutex::new(State::default()),
            client: OnceLock::new(),
            publish: Mutex::new(()),
            phase: AtomicU8::new(Phase::Uninitialized as u8),
            shutdown_requested: AtomicBool::new(false),
            runtime,
            background_nice: crate::background::level_below_caller(),
            syntax_hold: syntax_hold(),
        })
    }

    pub(crate) fn set_client(&self, client: Client) {
        let _ = self.client.set(client);
    }

    pub(crate) fn client(&self) -> Option<&Client> {
        self.client.get()
    }

    /// Locks the state. A panic while it was held (a bug) does not make the
    /// server unusable: the state is still consistent between operations.
    pub(crate) fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub(crate) fn phase(&self) -> Phase {
        match self.phase.load(Ordering::SeqCst) {
            1 => Phase::Running,
            2 => Phase::ShutDown,
            _ => Phase::Uninitialized,
        }
    }

    pub(crate) fn set_phase(&self, phase: Phase) {
        self.phase.store(phase as u8, Ordering::SeqCst);
    }

    /// Sends a `window/logMessage` without waiting for it.
    pub(crate) fn log(&self, typ: MessageType, message: impl Into<String>) {
        let message = message.into();
        if let Some(client) = self.client().cloned() {
            self.runtime.spawn(async move { client.log_message(typ, message).await });
        }
    }
}

/// What the client told us it can do.
#[derive(Debug, Default, Clone)]
pub(crate) struct ClientCaps {
    pub(crate) work_done_progress: bool,
    pub(crate) configuration: bool,
    pub(crate) watched_files_registration: bool,
    pub(crate) line_folding_only: bool,
    pub(crate) hierarchical_symbols: bool,
    pub(crate) hover_markdown: bool,
    pub(crate) definition_links: bool,
    pub(crate) declaration_links: bool,
    pub(crate) prepare_rename: bool,
    pub(crate) code_lens_refresh: bool,
    /// The client runs `robosim.showDiagram` itself (diagram lenses).
    pub(crate) show_diagram: bool,
}

/// A document the client has open.
#[derive(Debug)]
pub(crate) struct OpenDoc {
    /// The client's version of the text.
    pub(crate) version: i32,
    /// The client's text, to which incremental changes apply.
    pub(crate) text: String,
    /// The language from `languageId`, if it says one.
    pub(crate) kind: Option<FileKind>,
    /// The diagnostics of the last complete check of this buffer, and the
    /// edits made since: until the next check completes, its semantic
    /// diagnostics move with the text (`diagnostics.rs`).
    pub(crate) checked: Option<Vec<robosim_ide::Diagnostic>>,
    pub(crate) edits: Vec<Edit>,
}

/// Edits kept for moving older diagnostics; past this many the older
/// diagnostics are dropped instead (typing without a pause long enough for
/// one complete check).
const MAX_EDITS: usize = 4096;

/// One model file known to the server.
#[derive(Debug)]
pub(crate) struct FileEntry {
    /// The file in the analysis; `None` once removed (its diagnostics are
    /// still to be cleared).
    pub(crate) file: Option<FileId>,
    /// The URI to report it under.
    pub(crate) uri: Uri,
    /// Bumped on every change of the text or of the file's presence: a
    /// result computed for an older `seq` is stale.
    pub(crate) seq: u64,
    /// The client's buffer, while it is open. It takes precedence over the
    /// disk.
    pub(crate) open: Option<OpenDoc>,
    /// Whether the file was found on disk under a workspace folder.
    pub(crate) on_disk: bool,
}

/// The state behind the lock.
#[derive(Debug, Default)]
pub(crate) struct State {
    pub(crate) host: AnalysisHost,
    /// By key: the path for `file:` URIs, the URI itself otherwise.
    pub(crate) files: HashMap<String, FileEntry>,
    next_seq: u64,
    pub(crate) roots: Vec<PathBuf>,
    /// Workspace folders being read from disk, and until when diagnostics
    /// wait for them: before the load, a name from a file not read yet
    /// would show as unresolved; the load ends with a pass over every file.
    pub(crate) loading: (u32, Option<std::time::Instant>),
    pub(crate) caps: ClientCaps,
    /// What was last published for files that are not open, to avoid
    /// sending the same list again when another file changes.
    /// With the version they were published for.
    pub(crate) published: HashMap<String, (Option<i32>, Vec<lsp::Diagnostic>)>,
    /// Verification jobs and results (`verify.rs`).
    pub(crate) verify: crate::verify::Verification,
}

impl State {
    /// A load of workspace folders starts.
    pub(crate) fn begin_load(&mut self) {
        // Diagnostics wait at most this long (a client that never answers
        // the load's requests must not silence them).
        const WAIT: std::time::Duration = std::time::Duration::from_secs(20);
        self.loading = (self.loading.0 + 1, Some(std::time::Instant::now() + WAIT));
    }

    /// A load of workspace folders ended.
    pub(crate) fn end_load(&mut self) {
        let n = self.loading.0.saturating_sub(1);
        self.loading = (n, if n == 0 { None } else { self.loading.1 });
    }

    /// Whether diagnostics wait for a load.
    pub(crate) fn diagnostics_wait(&self) -> bool {
        self.loading.0 > 0 && self.loading.1.is_some_and(|t| std::time::Instant::now() < t)
    }
}

/// The key of a URI: its path for `file:` URIs (so that a file opened in
/// the editor and found on disk are one), the URI text otherwise.
pub(crate) fn key_of(uri: &Uri) -> String {
    if uri.scheme().as_str().eq_ignore_ascii_case("file") {
        if let Some(path) = uri.to_file_path() {
            return path.to_string_lossy().into_owned();
        }
    }
    uri.as_str().to_string()
}

/// The URI of a path found on disk.
pub(crate) fn uri_of_path(path: &std::path::Path) -> Option<Uri> {
    Uri::from_file_path(path)
}

/// The language a `languageId` names, if it names one of ours.
pub(crate) fn kind_of_language(language_id: &str) -> Option<FileKind> {
    match language_id {
        "robochart" => Some(FileKind::RoboChart),
        "robosim" => Some(FileKind::RoboSim),
        "robochart-assertions" => Some(FileKind::Assertions),
        "robosim-assertions" => Some(FileKind::SimAssertions),
        _ => None,
    }
}

/// A change to apply, with what went wrong on the way (for the log).
pub(crate) struct Applied {
    pub(crate) key: String,
    pub(crate) seq: u64,
    pub(crate) warnings: Vec<String>,
}

impl State {
    fn bump(&mut self) -> u64 {
        self.next_seq += 1;
        self.next_seq
    }

    /// The entry of `key` if it is the one a result for `seq` was computed
    /// from.
    pub(crate) fn current(&self, key: &str, seq: u64) -> Option<&FileEntry> {
        self.files.get(key).filter(|e| e.seq == seq)
    }

    /// The URI under which to report the file at `path`.
    pub(crate) fn uri_for_path(&self, path: &str) -> Option<Uri> {
        match self.files.get(path) {
            Some(e) => Some(e.uri.clone()),
            None => uri_of_path(std::path::Path::new(path)),
        }
    }

    pub(crate) fn open(&mut self, doc: lsp::TextDocumentItem) -> Applied {
        let key = key_of(&doc.uri);
        let kind = kind_of_language(&doc.language_id);
        let mut warnings = Vec::new();
        if self.files.get(&key).is_some_and(|e| e.open.is_some()) {
            warnings.push(format!("`{}` was opened twice; the new text replaces the old", doc.uri.as_str()));
        }
        self.before_write(&key, Some(&doc.text), kind);
        let file = self.host.set_file(&key, doc.text.clone(), kind, Durability::LOW);
        let seq = self.bump();
        let open = OpenDoc { version: doc.version, text: doc.text, kind, checked: None, edits: Vec::new() };
        let entry = self.files.entry(key.clone()).or_insert(FileEntry {
            file: None,
            uri: doc.uri.clone(),
            seq,
            open: None,
            on_disk: false,
        });
        entry.file = Some(file);
        entry.uri = doc.uri;
        entry.seq = seq;
        entry.open = Some(open);
        Applied { key, seq, warnings }
    }

    /// Applies the changes in order. `None` when the document is not open.
    pub(crate) fn change(&mut self, params: lsp::DidChangeTextDocumentParams) -> Option<Applied> {
        let key = key_of(&params.text_document.uri);
        let mut warnings = Vec::new();
        let entry = self.files.get_mut(&key)?;
        let doc = entry.open.as_mut()?;
        if params.text_document.version <= doc.version {
            warnings.push(format!(
                "version {} of `{}` does not follow version {}; applied anyway",
                params.text_document.version,
                params.text_document.uri.as_str(),
                doc.version
            ));
        }
        for change in params.content_changes {
            match change.range {
                None => {
                    doc.text = change.text;
                    doc.checked = None;
                    doc.edits.clear();
                }
                Some(range) => {
                    let index = LineIndex::new(&doc.text);
                    let t = Text { text: &doc.text, index: &index };
                    let (mut start, moved_start) = t.offset(range.start);
                    let (mut end, moved_end) = t.offset(range.end);
                    if moved_start || moved_end {
                        warnings.push(format!(
                            "change at {}:{}–{}:{} lies beyond the text of `{}` (version {}); clamped to it",
                            range.start.line,
                            range.start.character,
                            range.end.line,
                            range.end.character,
                            params.text_document.uri.as_str(),
                            params.text_document.version
                        ));
                    }
                    if start > end {
                        warnings.push(format!(
                            "change range of `{}` ends before it starts; swapped",
                            params.text_document.uri.as_str()
                        ));
                        std::mem::swap(&mut start, &mut end);
                    }
                    if doc.checked.is_some() {
                        let edit = Edit { delete: TextRange::new(start, end), insert_len: TextSize::of(&change.text) };
                        doc.edits.push(edit);
                    }
                    doc.text.replace_range(usize::from(start)..usize::from(end), &change.text);
                }
            }
        }
        if doc.edits.len() > MAX_EDITS {
            doc.checked = None;
            doc.edits.clear();
        }
        doc.version = params.text_document.version;
        let text = doc.text.clone();
        let kind = doc.kind;
        self.before_write(&key, Some(&text), kind);
        let file = self.host.set_file(&key, text, kind, Durability::LOW);
        let seq = self.bump();
        let entry = self.files.get_mut(&key)?;
        entry.file = Some(file);
        entry.seq = seq;
        Some(Applied { key, seq, warnings })
    }

    /// Closes a document. A file that is also on disk stays in the
    /// workspace (its disk text is read back by the caller); any other is
    /// removed and its diagnostics cleared. `None` when it was not open.
    pub(crate) fn close(&mut self, uri: &Uri) -> Option<(Applied, bool)> {
        let key = key_of(uri);
        let entry = self.files.get_mut(&key)?;
        entry.open.take()?;
        let on_disk = entry.on_disk;
        if !on_disk {
            self.before_write(&key, None, None);
            self.host.remove_file(&key);
        }
        let seq = self.bump();
        let entry = self.files.get_mut(&key)?;
        entry.seq = seq;
        if !on_disk {
            entry.file = None;
        }
        Some((Applied { key, seq, warnings: Vec::new() }, on_disk))
    }

    /// Sets the disk text of a workspace file, unless the client has it
    /// open (its buffer wins). Returns the new `seq` when something changed.
    pub(crate) fn set_disk_file(&mut self, path: &str, text: String) -> Option<u64> {
        if let Some(entry) = self.files.get_mut(path) {
            entry.on_disk = true;
            if entry.open.is_some() {
                return None;
            }
        }
        let uri = self.uri_for_path(path)?;
        self.before_write(path, Some(&text), None);
        let file = self.host.set_file(path, text, None, Durability::MEDIUM);
        let seq = self.bump();
        let entry =
            self.files.entry(path.to_string()).or_insert(FileEntry { file: None, uri, seq, open: None, on_disk: true });
        entry.file = Some(file);
        entry.seq = seq;
        entry.on_disk = true;
        Some(seq)
    }

    /// Removes a workspace file deleted from disk, unless it is open.
    /// Returns the new `seq` when it was removed.
    pub(crate) fn remove_disk_file(&mut self, path: &str) -> Option<u64> {
        let entry = self.files.get_mut(path)?;
        entry.on_disk = false;
        if entry.open.is_some() || entry.file.is_none() {
            return None;
        }
        self.before_write(path, None, None);
        self.host.remove_file(path);
        let seq = self.bump();
        let entry = self.files.get_mut(path)?;
        entry.file = None;
        entry.seq = seq;
        Some(seq)
    }

    /// Every file with its `seq`, for a full diagnostics pass.
    pub(crate) fn all_files(&self) -> Vec<(String, u64)> {
        let mut all: Vec<(String, u64)> = self.files.iter().map(|(k, e)| (k.clone(), e.seq)).collect();
        all.sort();
        all
    }

    pub(crate) fn set_rules(&mut self, rules: RuleSet) -> bool {
        let changed = self.host.rules() != rules;
        if changed {
            // The write waits for the verification jobs' snapshots.
            self.verify.cancel_all();
        }
        self.host.set_rules(rules);
        changed
    }

    /// Called before a write of `path` (`text: None` for a removal): when
    /// it changes the workspace's text, running verification jobs stop (the
    /// write waits for their snapshots) and their results become stale.
    fn before_write(&mut self, path: &str, text: Option<&str>, kind: Option<FileKind>) {
        let changes = match text {
            Some(text) => self.host.would_change(path, text, kind),
            None => self.host.file_id(path).is_some(),
        };
        if changes {
            self.verify.invalidate();
        }
    }
}
