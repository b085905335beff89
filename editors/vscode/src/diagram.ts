// Diagrams in the editor: the `robosim.showDiagram` command opens a webview
// beside the editor with the diagram of a state machine, operation,
// controller or module, as the server draws it (`robosim/diagram`). The view
// follows the text: it asks again 300 ms after the last change to a model.
// Clicking a state, transition, block or connection moves the cursor to its
// declaration (the SVG's groups carry `data-line`/`data-character`). The
// view opens fitted to the window, zooms with the wheel and pans by
// dragging, and keeps its zoom across redraws.
//
// The page has a strict Content Security Policy: nothing is loaded from
// anywhere, the SVG is inline and the only script is the page's own, with a
// nonce. `diagramHtml` and `parseReveal` are pure, for the tests.

import { randomBytes } from "crypto";
import * as vscode from "vscode";

/** The command of the "◇ Show diagram" lenses: `[uri, element]`. */
export const SHOW_DIAGRAM = "robosim.showDiagram";
/** The server's request. */
export const DIAGRAM_REQUEST = "robosim/diagram";
/** How long the view waits after the last change before asking again. */
export const REFRESH_DELAY_MS = 300;

/** A source range as the diagram model gives it (0-based, UTF-16). */
export interface Span {
  start: number;
  end: number;
  line: number;
  character: number;
  endLine: number;
  endCharacter: number;
}

/** The part of the diagram model the view uses (`robosim diagram --json`). */
export interface DiagramModel {
  kind: "stateMachine" | "operation" | "controller" | "module";
  name: string;
  qualifiedName: string;
  file: string;
  nameRange: Span;
  range: Span;
}

/** The answer of `robosim/diagram`. */
export interface DiagramResult {
  uri: string;
  diagrams: { model: DiagramModel; svg: string }[];
}

/** Asks the server for the diagrams of `uri` (only `element` when given). */
export type RequestDiagrams = (uri: string, element: string | undefined) => Promise<DiagramResult>;

/** A position range to reveal, from a click in the view. */
export interface Reveal {
  start: { line: number; character: number };
  end: { line: number; character: number };
}

/** Escapes text for HTML content and attribute values. */
export function escapeHtml(s: string): string {
  return s.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;").replace(/"/g, "&quot;").replace(/'/g, "&#39;");
}

/** A fresh nonce for the page's script. */
export function makeNonce(): string {
  return randomBytes(18).toString("base64").replace(/[+/=]/g, "");
}

/** What the page shows. */
export interface PageContent {
  /** The webview's `cspSource` (its own resources; nothing is loaded from it). */
  cspSource: string;
  /** The nonce of the page's script. */
  nonce: string;
  /** The page title. */
  title: string;
  /** The diagram, inline. */
  svg?: string;
  /** A message above the diagram (an error, "loading…"). */
  message?: string;
}

// The page's script: clicks go back to the extension, updates come in as
// messages (the panel is not reloaded on each edit, so the view stays).
// The view zooms (wheel, buttons) and pans (drag); it opens fitted to the
// window and follows the window's size until the user zooms or pans, and
// keeps its zoom and position across redraws and reloads (the webview's
// state). A drag is not a click: only a click without movement moves the
// cursor. Plain ES2017, no dependencies.
const PAGE_SCRIPT = `
(function () {
  const vscode = acquireVsCodeApi();
  const viewport = document.getElementById("viewport");
  const diagram = document.getElementById("diagram");
  const status = document.getElementById("status");
  const zoomText = document.getElementById("zoom");
  const MIN = 0.05, MAX = 8, MARGIN = 12, STEP = 1.25;
  const saved = vscode.getState();
  let view = saved && typeof saved.scale === "number" ? saved : { scale: 1, x: 0, y: 0, fit: true };
  let selected = null;
  let drag = null;
  let dragged = false;
  function clamp(k) { return Math.min(MAX, Math.max(MIN, k)); }
  function drawing() {
    const svg = diagram.querySelector("svg");
    if (!svg) return null;
    const w = Number(svg.getAttribute("width")), h = Number(svg.getAttribute("height"));
    return w > 0 && h > 0 ? { w: w, h: h } : null;
  }
  function apply() {
    diagram.style.transform = "translate(" + view.x + "px, " + view.y + "px) scale(" + view.scale + ")";
    zoomText.textContent = Math.round(view.scale * 100) + "%";
    vscode.setState(view);
  }
  // The whole drawing in the window, never enlarged past twice its size.
  function fit() {
    const d = drawing();
    if (!d) return;
    const vw = viewport.clientWidth, vh = viewport.clientHeight;
    const k = clamp(Math.min((vw - 2 * MARGIN) / d.w, (vh - 2 * MARGIN) / d.h, 2));
    view = { scale: k, x: Math.max(MARGIN, (vw - d.w * k) / 2), y: Math.max(MARGIN, (vh - d.h * k) / 2), fit: true };
    apply();
  }
  // Zooms by factor keeping the point (px, py) of the viewport in place.
  function zoomAt(factor, px, py) {
    const k = clamp(view.scale * factor);
    const f = k / view.scale;
    view = { scale: k, x: px - (px - view.x) * f, y: py - (py - view.y) * f, fit: false };
    apply();
  }
  function centre() { return [viewport.clientWidth / 2, viewport.clientHeight / 2]; }
  function select(g) {
    if (selected) selected.classList.remove("highlight");
    selected = g;
    if (g) g.classList.add("highlight");
  }
  viewport.addEventListener("wheel", function (event) {
    event.preventDefault();
    const r = viewport.getBoundingClientRect();
    zoomAt(Math.exp(-event.deltaY * 0.002), event.clientX - r.left, event.clientY - r.top);
  }, { passive: false });
  viewport.addEventListener("pointerdown", function (event) {
    if (event.button !== 0) return;
    drag = { x: event.clientX, y: event.clientY, vx: view.x, vy: view.y };
    dragged = false;
  });
  window.addEventListener("pointermove", function (event) {
    if (!drag) return;
    const dx = event.clientX - drag.x, dy = event.clientY - drag.y;
    if (!dragged && Math.abs(dx) + Math.abs(dy) < 4) return;
    dragged = true;
    viewport.classList.add("dragging");
    view = { scale: view.scale, x: drag.vx + dx, y: drag.vy + dy, fit: false };
    apply();
  });
  window.addEventListener("pointerup", function () {
    drag = null;
    viewport.classList.remove("dragging");
  });
  window.addEventListener("resize", function () { if (view.fit) fit(); });
  document.getElementById("fit").addEventListener("click", fit);
  document.getElementById("zoom-in").addEventListener("click", function () { const c = centre(); zoomAt(STEP, c[0], c[1]); });
  document.getElementById("zoom-out").addEventListener("click", function () { const c = centre(); zoomAt(1 / STEP, c[0], c[1]); });
  document.addEventListener("click", function (event) {
    if (dragged) { dragged = false; return; }
    const target = event.target;
    const g = target && target.closest ? target.closest("[data-line]") : null;
    if (!g) return;
    select(g);
    const num = function (name) { return Number(g.getAttribute(name)); };
    vscode.postMessage({
      type: "reveal",
      line: num("data-line"),
      character: num("data-character"),
      endLine: num("data-end-line"),
      endCharacter: num("data-end-character"),
    });
  });
  window.addEventListener("message", function (event) {
    const m = event.data;
    if (!m || m.type !== "update") return;
    if (typeof m.svg === "string") {
      diagram.innerHTML = m.svg;
      selected = null;
      // A redraw keeps the user's zoom; a fitted view fits the new drawing.
      if (view.fit) fit(); else apply();
    }
    status.textContent = m.message || "";
    status.hidden = !m.message;
    document.body.classList.toggle("stale", Boolean(m.stale));
  });
  if (view.fit) fit(); else apply();
  vscode.postMessage({ type: "ready" });
})();
`;

/** The webview page: a strict CSP, the SVG inline, a nonce'd script. */
export function diagramHtml(page: PageContent): string {
  const csp = [
    "default-src 'none'",
    // The SVG's own <style> and the page's: styles only, never scripts.
    `style-src ${page.cspSource} 'unsafe-inline'`,
    `script-src 'nonce-${page.nonce}'`,
  ].join("; ");
  const message = page.message ?? "";
  return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="UTF-8">
<meta http-equiv="Content-Security-Policy" content="${escapeHtml(csp)}">
<meta name="viewport" content="width=device-width, initial-scale=1.0">
<title>${escapeHtml(page.title)}</title>
<style>
  html, body { height: 100%; }
  body { margin: 0; display: flex; flex-direction: column; background: var(--vscode-editor-background); color: var(--vscode-foreground); font-family: var(--vscode-font-family); }
  #toolbar { display: flex; gap: 4px; align-items: center; padding: 4px 8px; }
  #toolbar button { color: var(--vscode-button-secondaryForeground, inherit); background: var(--vscode-button-secondaryBackground, transparent); border: 1px solid var(--vscode-contrastBorder, transparent); padding: 1px 8px; cursor: pointer; }
  #zoom { min-width: 4em; opacity: 0.8; }
  #status { margin: 0 8px 4px 8px; padding: 4px 8px; border-left: 3px solid var(--vscode-editorWarning-foreground, #c09000); }
  #viewport { flex: 1; position: relative; overflow: hidden; cursor: grab; touch-action: none; }
  #viewport.dragging { cursor: grabbing; }
  #diagram { position: absolute; left: 0; top: 0; transform-origin: 0 0; }
  #diagram svg { display: block; background: #ffffff; }
  body.stale #diagram { opacity: 0.5; }
</style>
</head>
<body>
<div id="toolbar"><button id="fit" title="Fit to window">Fit</button><button id="zoom-out" title="Zoom out">−</button><button id="zoom-in" title="Zoom in">+</button><span id="zoom"></span><span>wheel to zoom, drag to move</span></div>
<div id="status"${message ? "" : " hidden"}>${escapeHtml(message)}</div>
<div id="viewport"><div id="diagram">${page.svg ?? ""}</div></div>
<script nonce="${page.nonce}">${PAGE_SCRIPT}</script>
</body>
</html>
`;
}

const isIndex = (v: unknown): v is number => typeof v === "number" && Number.isInteger(v) && v >= 0;

/** The range of a `reveal` message from the page, or `undefined`. */
export function parseReveal(message: unknown): Reveal | undefined {
  if (typeof message !== "object" || message === null) return undefined;
  const m = message as Record<string, unknown>;
  if (m.type !== "reveal" || !isIndex(m.line) || !isIndex(m.character)) return undefined;
  const start = { line: m.line, character: m.character };
  const endOk = isIndex(m.endLine) && isIndex(m.endCharacter);
  const end = endOk ? { line: m.endLine as number, character: m.endCharacter as number } : start;
  const after = end.line > start.line || (end.line === start.line && end.character >= start.character);
  return { start, end: after ? end : start };
}

/** The message that says why a request failed. */
function errorText(e: unknown): string {
  return e instanceof Error ? e.message : String(e);
}

/** One open diagram view: the diagram of `element` in `uri`. */
class DiagramView {
  private seq = 0;
  private applied = 0;
  private timer: ReturnType<typeof setTimeout> | undefined;
  private svg: string | undefined;
  private message: string | undefined;
  private stale = false;

  constructor(
    readonly panel: vscode.WebviewPanel,
    readonly uri: string,
    readonly element: string,
    private readonly source: vscode.ViewColumn | undefined,
    private readonly request: RequestDiagrams,
    private readonly delay: number,
  ) {
    panel.webview.onDidReceiveMessage((m) => this.onMessage(m));
  }

  /** Shows `result` (the first diagram), or an error above the last one. */
  apply(result: DiagramResult | undefined, error: string | undefined): void {
    const d = result?.diagrams[0];
    if (d) {
      this.svg = d.svg;
      this.message = undefined;
      this.stale = false;
      this.panel.title = `◇ ${d.model.name}`;
    } else {
      this.message = error ?? `${this.element} has no diagram`;
      this.stale = this.svg !== undefined;
    }
    this.post();
  }

  private post(): void {
    void this.panel.webview.postMessage({ type: "update", svg: this.svg, message: this.message, stale: this.stale });
  }

  /** Asks the server again; answers older than the last one shown are dropped. */
  async refresh(): Promise<void> {
    const seq = ++this.seq;
    let result: DiagramResult | undefined;
    let error: string | undefined;
    try {
      result = await this.request(this.uri, this.element);
    } catch (e) {
      error = errorText(e);
    }
    if (seq < this.applied) return;
    this.applied = seq;
    this.apply(result, error);
  }

  /** Asks again `delay` ms after the last call. */
  schedule(): void {
    if (this.timer) clearTimeout(this.timer);
    this.timer = setTimeout(() => {
      this.timer = undefined;
      void this.refresh();
    }, this.delay);
  }

  dispose(): void {
    if (this.timer) clearTimeout(this.timer);
    this.timer = undefined;
  }

  private onMessage(message: unknown): void {
    if (typeof message === "object" && message !== null && (message as { type?: unknown }).type === "ready") {
      // A page (re)loaded, after being hidden: it gets the latest diagram.
      if (this.svg !== undefined || this.message !== undefined) this.post();
      return;
    }
    const reveal = parseReveal(message);
    if (reveal) void this.reveal(reveal);
  }

  /** Moves the cursor to the start of `r` in the source, showing all of `r`. */
  private async reveal(r: Reveal): Promise<void> {
    const uri = vscode.Uri.parse(this.uri);
    const start = new vscode.Position(r.start.line, r.start.character);
    const end = new vscode.Position(r.end.line, r.end.character);
    const shown = vscode.window.visibleTextEditors.find((e) => e.document.uri.toString() === uri.toString());
    const column = shown?.viewColumn ?? this.source ?? vscode.ViewColumn.One;
    const doc = await vscode.workspace.openTextDocument(uri);
    const editor = await vscode.window.showTextDocument(doc, {
      viewColumn: column,
      preserveFocus: false,
      selection: new vscode.Range(start, start),
    });
    editor.revealRange(new vscode.Range(start, end), vscode.TextEditorRevealType.InCenterIfOutsideViewport);
  }
}

/** Options of {@link DiagramViews}. */
export interface DiagramViewsOptions {
  /** Sends `robosim/diagram`. */
  request: RequestDiagrams;
  /** The languages whose edits refresh the views. */
  languages: readonly string[];
  /** The debounce delay (default {@link REFRESH_DELAY_MS}). */
  delay?: number;
}

/** The diagram views: one per element, refreshed as the models change. */
export class DiagramViews implements vscode.Disposable {
  private readonly views = new Map<string, DiagramView>();
  private readonly listener: vscode.Disposable;
  private readonly diagnostics: vscode.Disposable;
  private readonly delay: number;

  constructor(private readonly options: DiagramViewsOptions) {
    this.delay = options.delay ?? REFRESH_DELAY_MS;
    // A diagram can depend on other files (a machine's RoboSim inputs and
    // outputs): an edit of any model refreshes every view.
    this.listener = vscode.workspace.onDidChangeTextDocument((e) => {
      if (e.contentChanges.length === 0 || !options.languages.includes(e.document.languageId)) return;
      for (const view of this.views.values()) view.schedule();
    });
    // A verification's result arrives as diagnostics: the server then draws
    // its counterexample on the diagrams, so they are asked for again.
    this.diagnostics = vscode.languages.onDidChangeDiagnostics(() => {
      for (const view of this.views.values()) view.schedule();
    });
  }

  /**
   * The command: `[uri, element]` from a lens. From the command palette,
   * the active editor's document and, when it has several diagrams, the
   * one picked.
   */
  async show(uri?: unknown, element?: unknown): Promise<void> {
    let target = typeof uri === "string" ? uri : undefined;
    const editor = vscode.window.activeTextEditor;
    if (!target) {
      if (!editor || !this.options.languages.includes(editor.document.languageId)) {
        void vscode.window.showInformationMessage("Open a RoboChart or RoboSim model to see its diagrams.");
        return;
      }
      target = editor.document.uri.toString();
    }
    let name = typeof element === "string" ? element : undefined;
    let first: DiagramResult;
    try {
      first = await this.options.request(target, name);
    } catch (e) {
      void vscode.window.showErrorMessage(`No diagram: ${errorText(e)}`);
      return;
    }
    if (first.diagrams.length === 0) {
      void vscode.window.showInformationMessage("This file declares no state machine, operation, controller or module.");
      return;
    }
    if (!name) {
      const picked =
        first.diagrams.length === 1
          ? first.diagrams[0]
          : await vscode.window.showQuickPick(
              first.diagrams.map((d) => ({ label: d.model.qualifiedName, description: d.model.kind, d })),
              { placeHolder: "The diagram to show" },
            ).then((p) => p?.d);
      if (!picked) return;
      name = picked.model.qualifiedName;
      first = { uri: first.uri, diagrams: [picked] };
    }
    const key = `${target}\n${name}`;
    const existing = this.views.get(key);
    if (existing) {
      existing.panel.reveal(undefined, true);
      existing.apply(first, undefined);
      return;
    }
    const d = first.diagrams[0];
    const panel = vscode.window.createWebviewPanel(
      "robosim.diagram",
      `◇ ${d.model.name}`,
      { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
      { enableScripts: true, enableCommandUris: false, localResourceRoots: [] },
    );
    panel.webview.html = diagramHtml({
      cspSource: panel.webview.cspSource,
      nonce: makeNonce(),
      title: d.model.qualifiedName,
      svg: d.svg,
    });
    const source = editor?.document.uri.toString() === target ? editor.viewColumn : undefined;
    const view = new DiagramView(panel, target, name, source, this.options.request, this.delay);
    view.apply(first, undefined);
    this.views.set(key, view);
    panel.onDidDispose(() => {
      view.dispose();
      this.views.delete(key);
    });
  }

  /** The open views, by `uri\nelement` (for tests). */
  get open(): string[] {
    return [...this.views.keys()];
  }

  dispose(): void {
    this.listener.dispose();
    this.diagnostics.dispose();
    for (const view of this.views.values()) {
      view.dispose();
      view.panel.dispose();
    }
    this.views.clear();
  }
}
