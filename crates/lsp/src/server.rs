//! The request and notification handlers (document synchronisation is in
//! `ordered.rs`). Requests run their query on a blocking thread with a
//! snapshot, so handlers never hold the state lock while computing.

use std::path::PathBuf;
use std::sync::Arc;

use robosim_ide::{Analysis, Cancellable, FileId};
use tower_lsp_server::jsonrpc::{Error, ErrorCode, Result};
use tower_lsp_server::ls_types::*;
use tower_lsp_server::{Client, LanguageServer};

use crate::convert::{self, Text};
use crate::state::{key_of, ClientCaps, Phase, Shared};
use crate::workspace;

/// The language server proper.
pub(crate) struct Backend {
    pub(crate) shared: Arc<Shared>,
}

impl Backend {
    pub(crate) fn new(client: Client, shared: Arc<Shared>) -> Backend {
        shared.set_client(client);
        Backend { shared }
    }

    /// Runs `f` on a snapshot with the file of `uri`, off the async
    /// threads. A run cancelled by an edit is retried on the new text (the
    /// client wants the answer for what it has now); after repeated edits
    /// the request fails with `ContentModified`.
    async fn with_file<T, F>(&self, uri: &Uri, f: F) -> Result<T>
    where
        T: Send + 'static,
        F: Fn(&Analysis, FileId, &ClientCaps) -> Cancellable<T> + Send + Sync + 'static,
    {
        let f = Arc::new(f);
        for _ in 0..3 {
            let (analysis, file, caps) = {
                let st = self.shared.lock();
                let file = st.files.get(&key_of(uri)).and_then(|e| e.file).ok_or_else(|| unknown_document(uri))?;
                (st.host.analysis(), file, st.caps.clone())
            };
            let f = f.clone();
            match tokio::task::spawn_blocking(move || f(&analysis, file, &caps)).await {
                Ok(Ok(v)) => return Ok(v),
                Ok(Err(_cancelled)) => continue,
                Err(e) => return Err(internal(format!("the request failed: {e}"))),
            }
        }
        Err(Error::content_modified())
    }
}

fn unknown_document(uri: &Uri) -> Error {
    Error {
        code: ErrorCode::InvalidParams,
        message: format!("`{}` is not an open document or a model file of the workspace", uri.as_str()).into(),
        data: None,
    }
}

fn internal(message: String) -> Error {
    Error { code: ErrorCode::InternalError, message: message.into(), data: None }
}

fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        position_encoding: Some(PositionEncodingKind::UTF16),
        text_document_sync: Some(TextDocumentSyncCapability::Options(TextDocumentSyncOptions {
            open_close: Some(true),
            change: Some(TextDocumentSyncKind::INCREMENTAL),
            will_save: None,
            will_save_wait_until: None,
            save: None,
        })),
        document_symbol_provider: Some(OneOf::Left(true)),
        workspace_symbol_provider: Some(OneOf::Left(true)),
        semantic_tokens_provider: Some(SemanticTokensServerCapabilities::SemanticTokensOptions(
            SemanticTokensOptions {
                work_done_progress_options: WorkDoneProgressOptions::default(),
                legend: convert::semantic_tokens_legend(),
                range: None,
                full: Some(SemanticTokensFullOptions::Bool(true)),
            },
        )),
        folding_range_provider: Some(FoldingRangeProviderCapability::Simple(true)),
        selection_range_provider: Some(SelectionRangeProviderCapability::Simple(true)),
        workspace: Some(WorkspaceServerCapabilities {
            workspace_folders: Some(WorkspaceFoldersServerCapabilities {
                supported: Some(true),
                change_notifications: Some(OneOf::Left(true)),
            }),
            file_operations: None,
        }),
        ..ServerCapabilities::default()
    }
}

fn client_caps(c: &ClientCapabilities) -> ClientCaps {
    let ws = c.workspace.as_ref();
    let td = c.text_document.as_ref();
    ClientCaps {
        work_done_progress: c.window.as_ref().and_then(|w| w.work_done_progress).unwrap_or(false),
        configuration: ws.and_then(|w| w.configuration).unwrap_or(false),
        watched_files_registration: ws
            .and_then(|w| w.did_change_watched_files.as_ref())
            .and_then(|d| d.dynamic_registration)
            .unwrap_or(false),
        line_folding_only: td.and_then(|t| t.folding_range.as_ref()).and_then(|f| f.line_folding_only).unwrap_or(false),
        hierarchical_symbols: td
            .and_then(|t| t.document_symbol.as_ref())
            .and_then(|d| d.hierarchical_document_symbol_support)
            .unwrap_or(false),
    }
}

fn folder_path(uri: &Uri) -> Option<PathBuf> {
    let key = key_of(uri);
    let path = PathBuf::from(key);
    path.is_absolute().then_some(path)
}

impl LanguageServer for Backend {
    async fn initialize(&self, params: InitializeParams) -> Result<InitializeResult> {
        let mut roots: Vec<PathBuf> = params
            .workspace_folders
            .as_deref()
            .unwrap_or_default()
            .iter()
            .filter_map(|f| folder_path(&f.uri))
            .collect();
        #[allow(deprecated)] // Older clients only send `rootUri`.
        if roots.is_empty() {
            roots.extend(params.root_uri.as_ref().and_then(folder_path));
        }
        {
            let mut st = self.shared.lock();
            st.caps = client_caps(&params.capabilities);
            st.roots = roots;
        }
        if let Some(rules) = params.initialization_options.as_ref().and_then(workspace::rules_from_settings) {
            match rules {
                // No snapshot exists yet, so this write cannot wait.
                Ok(r) => {
                    self.shared.lock().set_rules(r);
                }
                Err(msg) => self.shared.log(MessageType::WARNING, msg),
            }
        }
        self.shared.set_phase(Phase::Running);
        Ok(InitializeResult {
            capabilities: capabilities(),
            server_info: Some(ServerInfo {
                name: "robosim".to_string(),
                version: Some(env!("CARGO_PKG_VERSION").into()),
            }),
            offset_encoding: None,
        })
    }

    async fn initialized(&self, _: InitializedParams) {
        // In a task of its own: these wait for client replies, and a
        // handler slot must not be held meanwhile.
        let shared = self.shared.clone();
        tokio::spawn(async move {
            workspace::register_watchers(&shared).await;
            workspace::pull_configuration(&shared).await;
            let roots = shared.lock().roots.clone();
            workspace::load_roots(shared, roots).await;
        });
    }

    async fn shutdown(&self) -> Result<()> {
        self.shared.set_phase(Phase::ShutDown);
        self.shared.shutdown_requested.store(true, std::sync::atomic::Ordering::SeqCst);
        Ok(())
    }

    async fn did_change_configuration(&self, params: DidChangeConfigurationParams) {
        match workspace::rules_from_settings(&params.settings) {
            Some(rules) => workspace::apply_rules(&self.shared, rules),
            // VS Code sends `null` settings and expects a pull.
            None => {
                let shared = self.shared.clone();
                tokio::spawn(async move { workspace::pull_configuration(&shared).await });
            }
        }
    }

    async fn did_change_watched_files(&self, params: DidChangeWatchedFilesParams) {
        workspace::watched_files_changed(&self.shared, params.changes);
    }

    async fn did_change_workspace_folders(&self, params: DidChangeWorkspaceFoldersParams) {
        let removed: Vec<PathBuf> = params.event.removed.iter().filter_map(|f| folder_path(&f.uri)).collect();
        let added: Vec<PathBuf> = params.event.added.iter().filter_map(|f| folder_path(&f.uri)).collect();
        {
            let mut st = self.shared.lock();
            st.roots.retain(|r| !removed.contains(r));
            st.roots.extend(added.iter().cloned());
        }
        for root in &removed {
            workspace::unload_root(&self.shared, root);
        }
        if !added.is_empty() {
            let shared = self.shared.clone();
            tokio::spawn(workspace::load_roots(shared, added));
        }
    }

    async fn document_symbol(&self, params: DocumentSymbolParams) -> Result<Option<DocumentSymbolResponse>> {
        let uri = params.text_document.uri;
        let uri2 = uri.clone();
        let response = self
            .with_file(&uri, move |a, file, caps| {
                let symbols = a.document_symbols(file)?;
                let text = a.file_text(file)?;
                let index = a.line_index(file)?;
                let t = Text { text: &text, index: &index };
                Ok(if caps.hierarchical_symbols {
                    DocumentSymbolResponse::Nested(symbols.iter().map(|s| convert::document_symbol(t, s)).collect())
                } else {
                    let mut flat = Vec::new();
                    convert::flat_symbols(t, &uri2, &symbols, None, &mut flat);
                    DocumentSymbolResponse::Flat(flat)
                })
            })
            .await?;
        Ok(Some(response))
    }

    async fn symbol(&self, params: WorkspaceSymbolParams) -> Result<Option<WorkspaceSymbolResponse>> {
        let query = Arc::new(params.query);
        for _ in 0..3 {
            let (analysis, uris) = {
                let st = self.shared.lock();
                let uris: std::collections::HashMap<String, Uri> =
                    st.files.iter().map(|(k, e)| (k.clone(), e.uri.clone())).collect();
                (st.host.analysis(), uris)
            };
            let query = query.clone();
            let found = tokio::task::spawn_blocking(move || workspace_symbols(&analysis, &query, &uris)).await;
            match found {
                Ok(Ok(list)) => return Ok(Some(WorkspaceSymbolResponse::Flat(list))),
                Ok(Err(_cancelled)) => continue,
                Err(e) => return Err(internal(format!("the request failed: {e}"))),
            }
        }
        Err(Error::content_modified())
    }

    async fn semantic_tokens_full(&self, params: SemanticTokensParams) -> Result<Option<SemanticTokensResult>> {
        let tokens = self
            .with_file(&params.text_document.uri, |a, file, _| {
                let ranges = a.highlight(file)?;
                let text = a.file_text(file)?;
                let index = a.line_index(file)?;
                Ok(convert::semantic_tokens(Text { text: &text, index: &index }, &ranges))
            })
            .await?;
        Ok(Some(SemanticTokensResult::Tokens(SemanticTokens { result_id: None, data: tokens })))
    }

    async fn folding_range(&self, params: FoldingRangeParams) -> Result<Option<Vec<FoldingRange>>> {
        let folds = self
            .with_file(&params.text_document.uri, |a, file, caps| {
                let folds = a.folding_ranges(file)?;
                let text = a.file_text(file)?;
                let index = a.line_index(file)?;
                let t = Text { text: &text, index: &index };
                Ok(folds.iter().filter_map(|f| convert::folding_range(t, caps.line_folding_only, f)).collect())
            })
            .await?;
        Ok(Some(folds))
    }

    async fn selection_range(&self, params: SelectionRangeParams) -> Result<Option<Vec<SelectionRange>>> {
        let positions = params.positions;
        let ranges = self
            .with_file(&params.text_document.uri, move |a, file, _| {
                let text = a.file_text(file)?;
                let index = a.line_index(file)?;
                let t = Text { text: &text, index: &index };
                let offsets: Vec<_> = positions.iter().map(|p| t.offset(*p).0).collect();
                let ranges = a.selection_ranges(file, &offsets)?;
                Ok(ranges.iter().map(|r| convert::selection_range(t, r)).collect())
            })
            .await?;
        Ok(Some(ranges))
    }
}

fn workspace_symbols(
    analysis: &Analysis,
    query: &str,
    uris: &std::collections::HashMap<String, Uri>,
) -> Cancellable<Vec<SymbolInformation>> {
    let mut out = Vec::new();
    for s in analysis.workspace_symbols(query, 256)? {
        // The bundled library has no URI a client could open.
        if analysis.is_library(s.file)? {
            continue;
        }
        let Some(uri) = uris.get(&s.path).cloned().or_else(|| crate::diagnostics::uri_from_key(&s.path)) else {
            continue;
        };
        let text = analysis.file_text(s.file)?;
        let index = analysis.line_index(s.file)?;
        let t = Text { text: &text, index: &index };
        #[allow(deprecated)] // `deprecated` is a required field of the LSP type.
        out.push(SymbolInformation {
            name: s.name,
            kind: convert::symbol_kind(s.kind),
            tags: None,
            deprecated: None,
            location: Location::new(uri, t.range(s.selection_range)),
            container_name: s.container_name,
        });
    }
    Ok(out)
}
