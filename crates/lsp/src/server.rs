//! The request and notification handlers (document synchronisation is in
//! `ordered.rs`). Requests run their query on a blocking thread with a
//! snapshot, so handlers never hold the state lock while computing.

use std::path::PathBuf;
use std::sync::Arc;

use robosim_ide::{Analysis, Cancellable, FileId, SourceChange};
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
    pub(crate) async fn with_file<T, F>(&self, uri: &Uri, f: F) -> Result<T>
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

fn capabilities(caps: &ClientCaps) -> ServerCapabilities {
    ServerCapabilities {
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        declaration_provider: Some(DeclarationCapability::Simple(true)),
        references_provider: Some(OneOf::Left(true)),
        // Rename options (with `prepareProvider`) only for clients that
        // announce prepare support, as LSP requires.
        rename_provider: Some(if caps.prepare_rename {
            OneOf::Right(RenameOptions {
                prepare_provider: Some(true),
                work_done_progress_options: WorkDoneProgressOptions::default(),
            })
        } else {
            OneOf::Left(true)
        }),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some(vec!["$".to_string(), ":".to_string()]),
            resolve_provider: Some(false),
            ..CompletionOptions::default()
        }),
        document_formatting_provider: Some(OneOf::Left(true)),
        code_lens_provider: Some(CodeLensOptions { resolve_provider: Some(false) }),
        execute_command_provider: Some(ExecuteCommandOptions {
            commands: vec![crate::verify::COMMAND.to_string()],
            work_done_progress_options: WorkDoneProgressOptions::default(),
        }),
        code_action_provider: Some(CodeActionProviderCapability::Options(CodeActionOptions {
            code_action_kinds: Some(vec![CodeActionKind::QUICKFIX]),
            resolve_provider: Some(false),
            work_done_progress_options: WorkDoneProgressOptions::default(),
        })),
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
        // Markdown unless the client lists formats without it.
        hover_markdown: td
            .and_then(|t| t.hover.as_ref())
            .and_then(|h| h.content_format.as_ref())
            .is_none_or(|f| f.contains(&MarkupKind::Markdown)),
        definition_links: td.and_then(|t| t.definition.as_ref()).and_then(|d| d.link_support).unwrap_or(false),
        declaration_links: td.and_then(|t| t.declaration.as_ref()).and_then(|d| d.link_support).unwrap_or(false),
        prepare_rename: td.and_then(|t| t.rename.as_ref()).and_then(|r| r.prepare_support).unwrap_or(false),
        code_lens_refresh: ws.and_then(|w| w.code_lens.as_ref()).and_then(|c| c.refresh_support).unwrap_or(false),
        show_diagram: crate::diagram::client_shows_diagrams(c),
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
        let caps = client_caps(&params.capabilities);
        {
            let mut st = self.shared.lock();
            st.caps = caps.clone();
            // `initialized` loads them (`workspace::load_roots`).
            if !roots.is_empty() {
                st.begin_load();
            }
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
        if let Some(options) = &params.initialization_options {
            workspace::apply_verify_settings(&self.shared, options);
        }
        self.shared.set_phase(Phase::Running);
        Ok(InitializeResult {
            capabilities: capabilities(&caps),
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
        // Running checks are of no use any more.
        self.shared.lock().verify.cancel_all();
        self.shared.set_phase(Phase::ShutDown);
        self.shared.shutdown_requested.store(true, std::sync::atomic::Ordering::SeqCst);
        Ok(())
    }

    async fn did_change_configuration(&self, params: DidChangeConfigurationParams) {
        let verify = workspace::apply_verify_settings(&self.shared, &params.settings);
        match workspace::rules_from_settings(&params.settings) {
            Some(rules) => workspace::apply_rules(&self.shared, rules),
            None if verify => {}
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
            shared.lock().begin_load();
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

    async fn hover(&self, params: HoverParams) -> Result<Option<Hover>> {
        let p = params.text_document_position_params;
        let position = p.position;
        // The diagnostics of an open buffer are explained as they are shown:
        // the last complete check moved along with the edits since (the
        // parse adds the syntax ones), so the hover need not wait for the
        // check of a text just typed.
        let (shown, verified) = {
            let st = self.shared.lock();
            let key = key_of(&p.text_document.uri);
            let shown = st.files.get(&key).and_then(|e| {
                let (doc, file) = (e.open.as_ref()?, e.file?);
                Some(robosim_ide::carry_over(doc.checked.as_ref()?, file, &doc.edits))
            });
            (shown, st.verify.reports_for(&key))
        };
        self.with_file(&p.text_document.uri, move |a, file, caps| {
            let (text, index) = text_of(a, file)?;
            let t = Text { text: &text, index: &index };
            let offset = t.offset(position).0;
            let hover = match &shown {
                Some(carried) => {
                    let mut diags = a.syntax_diagnostics(file)?;
                    diags.extend(carried.iter().cloned());
                    a.hover_with_verification(file, offset, Some(&diags), &verified)?
                }
                None => a.hover_with_verification(file, offset, None, &verified)?,
            };
            let Some(h) = hover else { return Ok(None) };
            let kind = if caps.hover_markdown { MarkupKind::Markdown } else { MarkupKind::PlainText };
            Ok(Some(Hover {
                contents: HoverContents::Markup(MarkupContent { kind, value: h.markdown }),
                range: Some(t.range(h.range)),
            }))
        })
        .await
    }

    async fn goto_definition(&self, params: GotoDefinitionParams) -> Result<Option<GotoDefinitionResponse>> {
        let links = self.shared.lock().caps.definition_links;
        self.definition(params.text_document_position_params, links).await
    }

    async fn goto_declaration(
        &self,
        params: request::GotoDeclarationParams,
    ) -> Result<Option<request::GotoDeclarationResponse>> {
        // A name is declared where it is defined in these languages.
        let links = self.shared.lock().caps.declaration_links;
        self.definition(params.text_document_position_params, links).await
    }

    async fn references(&self, params: ReferenceParams) -> Result<Option<Vec<Location>>> {
        let p = params.text_document_position;
        let position = p.position;
        let include = params.context.include_declaration;
        let found = self
            .with_file(&p.text_document.uri, move |a, file, _| {
                let (text, index) = text_of(a, file)?;
                let t = Text { text: &text, index: &index };
                let Some(refs) = a.find_references(file, t.offset(position).0, include)? else { return Ok(None) };
                let mut out = Vec::with_capacity(refs.len());
                for r in refs {
                    // The bundled library has no file a client could open.
                    if a.is_library(r.file)? {
                        continue;
                    }
                    let (rt, ri) = text_of(a, r.file)?;
                    out.push((r.path, Text { text: &rt, index: &ri }.range(r.range)));
                }
                Ok(Some(out))
            })
            .await?;
        let Some(found) = found else { return Ok(None) };
        let st = self.shared.lock();
        Ok(Some(
            found.into_iter().filter_map(|(path, range)| Some(Location::new(uri_for(&st, &path)?, range))).collect(),
        ))
    }

    async fn prepare_rename(&self, params: TextDocumentPositionParams) -> Result<Option<PrepareRenameResponse>> {
        let position = params.position;
        self.with_file(&params.text_document.uri, move |a, file, _| {
            let (text, index) = text_of(a, file)?;
            let t = Text { text: &text, index: &index };
            Ok(a.prepare_rename(file, t.offset(position).0)?.map(|(range, placeholder)| {
                PrepareRenameResponse::RangeWithPlaceholder { range: t.range(range), placeholder }
            }))
        })
        .await?
        .map(Some)
        .map_err(|e| request_failed(e.to_string()))
    }

    async fn rename(&self, params: RenameParams) -> Result<Option<WorkspaceEdit>> {
        let p = params.text_document_position;
        let position = p.position;
        let new_name = params.new_name;
        let change = self
            .with_file(&p.text_document.uri, move |a, file, _| {
                let (text, index) = text_of(a, file)?;
                let t = Text { text: &text, index: &index };
                match a.rename(file, t.offset(position).0, &new_name)? {
                    Ok(change) => Ok(Ok(lsp_edits(a, &change)?)),
                    Err(e) => Ok(Err(e)),
                }
            })
            .await?
            .map_err(|e| request_failed(e.to_string()))?;
        Ok(Some(self.workspace_edit(change)?))
    }

    async fn completion(&self, params: CompletionParams) -> Result<Option<CompletionResponse>> {
        let p = params.text_document_position;
        let position = p.position;
        let items = self
            .with_file(&p.text_document.uri, move |a, file, _| {
                let (text, index) = text_of(a, file)?;
                let t = Text { text: &text, index: &index };
                let items = a.completions(file, t.offset(position).0)?;
                Ok(items.iter().map(|c| convert::completion_item(t, c)).collect())
            })
            .await?;
        Ok(Some(CompletionResponse::Array(items)))
    }

    async fn formatting(&self, params: DocumentFormattingParams) -> Result<Option<Vec<TextEdit>>> {
        self.with_file(&params.text_document.uri, |a, file, _| {
            let (text, index) = text_of(a, file)?;
            let t = Text { text: &text, index: &index };
            Ok(a.format(file)?
                .map(|edits| edits.iter().map(|e| TextEdit::new(t.range(e.range), e.new_text.clone())).collect()))
        })
        .await?
        .map(Some)
        .map_err(request_failed)
    }

    async fn code_lens(&self, params: CodeLensParams) -> Result<Option<Vec<CodeLens>>> {
        let (lenses, diagram_lenses) = self
            .with_file(&params.text_document.uri, |a, file, caps| {
                let lenses = a.verify_lenses(file)?;
                let (text, index) = text_of(a, file)?;
                let t = Text { text: &text, index: &index };
                let diagrams = if caps.show_diagram { crate::diagram::lenses(a, file)? } else { Vec::new() };
                Ok((lenses.into_iter().map(|l| (t.range(l.range), l)).collect::<Vec<_>>(), diagrams))
            })
            .await?;
        let st = self.shared.lock();
        let mut lenses: Vec<CodeLens> = lenses
            .into_iter()
            .filter_map(|(range, lens)| {
                let uri = uri_for(&st, lens.target.path())?;
                Some(CodeLens {
                    range,
                    command: Some(Command {
                        title: st.verify.lens_title(&lens),
                        command: crate::verify::COMMAND.to_string(),
                        arguments: Some(crate::verify::arguments(&uri, &lens.target)),
                    }),
                    data: None,
                })
            })
            .collect();
        // "◇ Show diagram" after the verification lens at the same place.
        let uri = &params.text_document.uri;
        lenses.extend(diagram_lenses.iter().map(|(range, lens)| crate::diagram::code_lens(uri, *range, lens)));
        lenses.sort_by_key(|l| (l.range.start.line, l.range.start.character));
        Ok(Some(lenses))
    }

    async fn execute_command(&self, params: ExecuteCommandParams) -> Result<Option<LSPAny>> {
        crate::verify::execute(&self.shared, params).await
    }

    async fn code_action(&self, params: CodeActionParams) -> Result<Option<CodeActionResponse>> {
        if let Some(only) = &params.context.only {
            if !only.iter().any(|k| CodeActionKind::QUICKFIX.as_str().starts_with(k.as_str())) {
                return Ok(Some(Vec::new()));
            }
        }
        let range = params.range;
        let sent = params.context.diagnostics;
        let actions = self
            .with_file(&params.text_document.uri, move |a, file, _| {
                let (text, index) = text_of(a, file)?;
                let t = Text { text: &text, index: &index };
                let (start, end) = (t.offset(range.start).0, t.offset(range.end).0);
                let range = robosim_ide::TextRange::new(start.min(end), start.max(end));
                let mut out = Vec::new();
                for assist in a.code_actions(file, range)? {
                    // The client's own diagnostic when it has it, so that it
                    // can tie the fix to what it shows.
                    let mine = convert::diagnostic(t, &assist.diagnostic, Vec::new());
                    let diagnostic = sent
                        .iter()
                        .find(|d| d.range == mine.range && d.code == mine.code && d.message == mine.message)
                        .cloned()
                        .unwrap_or(mine);
                    out.push((assist.title, diagnostic, lsp_edits(a, &assist.change)?));
                }
                Ok(out)
            })
            .await?;
        let mut response = Vec::with_capacity(actions.len());
        for (title, diagnostic, change) in actions {
            response.push(CodeActionOrCommand::CodeAction(CodeAction {
                title,
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: Some(vec![diagnostic]),
                edit: Some(self.workspace_edit(change)?),
                command: None,
                is_preferred: Some(true),
                disabled: None,
                data: None,
            }));
        }
        Ok(Some(response))
    }
}

impl Backend {
    async fn definition(&self, p: TextDocumentPositionParams, links: bool) -> Result<Option<GotoDefinitionResponse>> {
        let position = p.position;
        let found = self
            .with_file(&p.text_document.uri, move |a, file, _| {
                let (text, index) = text_of(a, file)?;
                let t = Text { text: &text, index: &index };
                let Some((origin, targets)) = a.goto_definition(file, t.offset(position).0)? else { return Ok(None) };
                let mut out = Vec::new();
                for nav in targets {
                    // The bundled library has no file a client could open.
                    if nav.is_library {
                        continue;
                    }
                    let (tt, ti) = text_of(a, nav.file)?;
                    let tt = Text { text: &tt, index: &ti };
                    out.push((nav.path, tt.range(nav.full_range), tt.range(nav.focus_range)));
                }
                Ok(Some((t.range(origin), out)))
            })
            .await?;
        let Some((origin, targets)) = found else { return Ok(None) };
        let st = self.shared.lock();
        let targets: Vec<(Uri, Range, Range)> =
            targets.into_iter().filter_map(|(path, full, focus)| Some((uri_for(&st, &path)?, full, focus))).collect();
        if targets.is_empty() {
            return Ok(None);
        }
        Ok(Some(if links {
            GotoDefinitionResponse::Link(
                targets
                    .into_iter()
                    .map(|(uri, full, focus)| LocationLink {
                        origin_selection_range: Some(origin),
                        target_uri: uri,
                        target_range: full,
                        target_selection_range: focus,
                    })
                    .collect(),
            )
        } else {
            GotoDefinitionResponse::Array(
                targets.into_iter().map(|(uri, _, focus)| Location::new(uri, focus)).collect(),
            )
        }))
    }

    /// A workspace edit from edits by path. A file without a URI the client
    /// could open fails the request rather than being skipped: a partial
    /// rename would break the model.
    fn workspace_edit(&self, files: Vec<(String, Vec<TextEdit>)>) -> Result<WorkspaceEdit> {
        let st = self.shared.lock();
        let mut changes = std::collections::HashMap::new();
        for (path, edits) in files {
            let uri = uri_for(&st, &path).ok_or_else(|| request_failed(format!("`{path}` cannot be edited")))?;
            changes.insert(uri, edits);
        }
        Ok(WorkspaceEdit { changes: Some(changes), document_changes: None, change_annotations: None })
    }
}

/// The text and line index of `file`.
pub(crate) fn text_of(a: &Analysis, file: FileId) -> Cancellable<(Arc<str>, Arc<robosim_ide::LineIndex>)> {
    Ok((a.file_text(file)?, a.line_index(file)?))
}

/// A source change as LSP edits, by path.
fn lsp_edits(a: &Analysis, change: &SourceChange) -> Cancellable<Vec<(String, Vec<TextEdit>)>> {
    let mut out = Vec::new();
    for fe in &change.files {
        let (text, index) = text_of(a, fe.file)?;
        let t = Text { text: &text, index: &index };
        out.push((
            fe.path.clone(),
            fe.edits.iter().map(|e| TextEdit::new(t.range(e.range), e.new_text.clone())).collect(),
        ));
    }
    Ok(out)
}

/// The URI a file of the workspace is reported under (`None` for the
/// bundled library).
fn uri_for(st: &crate::state::State, path: &str) -> Option<Uri> {
    match st.files.get(path) {
        Some(e) => Some(e.uri.clone()),
        None => crate::diagnostics::uri_from_key(path),
    }
}

/// LSP's `RequestFailed`: a valid request the server cannot carry out
/// (a refused rename, a file that cannot be formatted).
fn request_failed(message: String) -> Error {
    Error { code: ErrorCode::ServerError(-32803), message: message.into(), data: None }
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
