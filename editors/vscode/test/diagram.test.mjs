// The diagram view (src/diagram.ts, bundled into out/test/diagram.js) against
// a stand-in for `vscode`: the webview page (its Content Security Policy,
// the inline SVG, the nonce'd script and what its click handler posts, run
// in a `vm` context with a fake DOM), the `reveal` messages, and the views:
// the panel opened beside the editor, refreshed once 300 ms after a burst
// of edits, and a click that moves the cursor in the source.
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import Module, { createRequire } from "node:module";
import { dirname, join } from "node:path";
import { after, before, beforeEach, test } from "node:test";
import { fileURLToPath } from "node:url";
import vm from "node:vm";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const require = createRequire(import.meta.url);

// --- a stand-in for `vscode` ---------------------------------------------------

class Position {
  constructor(line, character) {
    this.line = line;
    this.character = character;
  }
}
class Range {
  constructor(start, end) {
    this.start = start;
    this.end = end;
  }
}

const state = {};
function reset() {
  Object.assign(state, {
    panels: [],
    changeListeners: [],
    diagnosticListeners: [],
    shown: [],
    revealed: [],
    errors: [],
    infos: [],
    activeTextEditor: undefined,
    visibleTextEditors: [],
  });
}
reset();

function makePanel(viewType, title, showOptions, options) {
  const panel = {
    viewType,
    title,
    showOptions,
    options,
    posted: [],
    receive: [],
    disposeListeners: [],
    revealedTimes: 0,
    webview: {
      html: "",
      cspSource: "vscode-webview://fake",
      postMessage(m) {
        panel.posted.push(m);
        return Promise.resolve(true);
      },
      onDidReceiveMessage(listener) {
        panel.receive.push(listener);
        return { dispose() {} };
      },
    },
    reveal() {
      panel.revealedTimes += 1;
    },
    onDidDispose(listener) {
      panel.disposeListeners.push(listener);
      return { dispose() {} };
    },
    dispose() {
      for (const l of panel.disposeListeners) l();
    },
    /** A message from the page. */
    send(m) {
      for (const l of panel.receive) l(m);
    },
  };
  return panel;
}

const fakeVscode = {
  Position,
  Range,
  ViewColumn: { Active: -1, Beside: -2, One: 1, Two: 2 },
  TextEditorRevealType: { Default: 0, InCenter: 1, InCenterIfOutsideViewport: 2, AtTop: 3 },
  Uri: { parse: (s) => ({ toString: () => s, fsPath: s.replace(/^file:\/\//, "") }) },
  window: {
    get activeTextEditor() {
      return state.activeTextEditor;
    },
    get visibleTextEditors() {
      return state.visibleTextEditors;
    },
    createWebviewPanel(...args) {
      const p = makePanel(...args);
      state.panels.push(p);
      return p;
    },
    showTextDocument(doc, options) {
      state.shown.push({ uri: doc.uri.toString(), options });
      return Promise.resolve({
        revealRange: (range, type) => state.revealed.push({ range, type }),
      });
    },
    showErrorMessage: (m) => {
      state.errors.push(m);
      return Promise.resolve(undefined);
    },
    showInformationMessage: (m) => {
      state.infos.push(m);
      return Promise.resolve(undefined);
    },
    showQuickPick: (items) => Promise.resolve(items[items.length - 1]),
  },
  languages: {
    onDidChangeDiagnostics(listener) {
      state.diagnosticListeners.push(listener);
      return { dispose() {} };
    },
  },
  workspace: {
    onDidChangeTextDocument(listener) {
      state.changeListeners.push(listener);
      return { dispose() {} };
    },
    openTextDocument: (uri) => Promise.resolve({ uri }),
  },
};

const originalLoad = Module._load;
let diagram;
before(() => {
  Module._load = function (request, ...rest) {
    if (request === "vscode") return fakeVscode;
    return originalLoad.call(this, request, ...rest);
  };
  diagram = require(join(root, "out", "test", "diagram.js"));
});
after(() => {
  Module._load = originalLoad;
});
beforeEach(reset);

const SVG =
  '<svg xmlns="http://www.w3.org/2000/svg" class="robosim-diagram" data-kind="stm" data-name="p::S">' +
  '<g class="node state" data-kind="state" data-id="Moving" data-start="10" data-end="40" data-line="3" ' +
  'data-character="4" data-end-line="5" data-end-character="5"><text>Moving</text></g></svg>';

// --- the page ------------------------------------------------------------------

/** The policy's directives, by name. */
function csp(html) {
  const m = html.match(/<meta http-equiv="Content-Security-Policy" content="([^"]*)">/);
  assert.ok(m, "the page has a Content-Security-Policy meta element");
  const directives = new Map();
  for (const part of m[1].replace(/&#39;/g, "'").split(";")) {
    const [name, ...values] = part.trim().split(/\s+/);
    directives.set(name, values);
  }
  return directives;
}

test("the page: a strict CSP, the SVG inline, one script with the nonce", () => {
  const html = diagram.diagramHtml({
    cspSource: "vscode-webview://abc",
    nonce: "N0nce123",
    title: "p::S <stm>",
    svg: SVG,
  });
  const policy = csp(html);
  assert.deepEqual(policy.get("default-src"), ["'none'"]);
  assert.deepEqual(policy.get("script-src"), ["'nonce-N0nce123'"], "only the nonce'd script runs");
  assert.ok(!policy.get("style-src").some((v) => /^https?:/.test(v)));
  assert.ok(![...policy.values()].flat().some((v) => /^(https?:|\*)/.test(v)), "nothing remote");
  assert.ok(html.includes(`<div id="diagram">${SVG}</div>`), "the SVG is inline, as given");
  const scripts = [...html.matchAll(/<script([^>]*)>/g)].map((m) => m[1]);
  assert.deepEqual(scripts, [' nonce="N0nce123"']);
  assert.ok(!/\son[a-z]+=/.test(html.replace(SVG, "")), "no inline event handlers");
  assert.ok(!/\b(src|href)=["']?https?:/.test(html), "no remote resources");
  assert.ok(html.includes("<title>p::S &lt;stm&gt;</title>"), "the title is escaped");
  // The click handler: the innermost group with a source range.
  assert.match(html, /addEventListener\("click"/);
  assert.match(html, /closest\("\[data-line\]"\)/);
  assert.match(html, /type: "reveal"/);

  const withMessage = diagram.diagramHtml({ cspSource: "x", nonce: "n", title: "t", message: "<b>error</b>" });
  assert.ok(withMessage.includes('<div id="status">&lt;b&gt;error&lt;/b&gt;</div>'));
  assert.ok(diagram.diagramHtml({ cspSource: "x", nonce: "n", title: "t" }).includes('<div id="status" hidden>'));
});

test("nonces are fresh and fit a CSP source expression", () => {
  const a = diagram.makeNonce();
  const b = diagram.makeNonce();
  assert.notEqual(a, b);
  assert.match(a, /^[A-Za-z0-9]{16,}$/);
});

/** An element of the fake DOM: listeners by type, classes, a style. */
function element(extra = {}) {
  const listeners = {};
  const set = new Set();
  return {
    listeners,
    style: {},
    classList: { add: (c) => set.add(c), remove: (c) => set.delete(c), toggle: (c, on) => (on ? set.add(c) : set.delete(c)), has: (c) => set.has(c) },
    addEventListener: (type, f) => (listeners[type] = f),
    ...extra,
  };
}

/**
 * Runs the page's script in a fake DOM; returns what it posted and the
 * handles. `state` is what the webview kept (`getState`); the viewport is
 * `width`×`height`.
 */
function runPage(html, { state: kept, width = 1000, height = 800 } = {}) {
  const script = html.match(/<script nonce="[^"]+">([\s\S]*?)<\/script>/)[1];
  const posted = [];
  const states = [];
  const listeners = {};
  const windowListeners = {};
  const diagramEl = element({
    innerHTML: html.match(/<div id="diagram">([\s\S]*?)<\/div><\/div>/)[1],
    // The drawing's size, from the SVG's attributes.
    querySelector(sel) {
      if (sel !== "svg") return null;
      const m = this.innerHTML.match(/<svg[^>]*>/);
      if (!m) return null;
      const attr = (n) => (m[0].match(new RegExp(` ${n}="([^"]*)"`)) || [])[1] ?? null;
      return { getAttribute: attr };
    },
  });
  const elements = {
    viewport: element({ clientWidth: width, clientHeight: height, getBoundingClientRect: () => ({ left: 10, top: 30 }) }),
    diagram: diagramEl,
    status: { textContent: "", hidden: true },
    zoom: { textContent: "" },
    fit: element(),
    "zoom-in": element(),
    "zoom-out": element(),
  };
  const body = element();
  const context = {
    // Messages cross realms as JSON, as they do from a webview.
    acquireVsCodeApi: () => ({
      postMessage: (m) => posted.push(JSON.parse(JSON.stringify(m))),
      getState: () => kept,
      setState: (s) => states.push(JSON.parse(JSON.stringify(s))),
    }),
    document: {
      body,
      getElementById: (id) => elements[id],
      addEventListener: (type, f) => (listeners[type] = f),
    },
    window: { addEventListener: (type, f) => (windowListeners[type] = f) },
    Number,
    Boolean,
    Math,
  };
  vm.runInNewContext(script, context);
  const view = () => states.at(-1);
  return { posted, states, view, listeners, windowListeners, elements, body };
}

test("the page's script: ready, a click posts the group's range, updates replace the SVG", () => {
  const page = runPage(diagram.diagramHtml({ cspSource: "x", nonce: "n", title: "t", svg: SVG }));
  assert.deepEqual(page.posted, [{ type: "ready" }]);
  const attrs = {
    "data-line": "3",
    "data-character": "4",
    "data-end-line": "5",
    "data-end-character": "5",
  };
  const group = { getAttribute: (n) => attrs[n], classList: { add() {}, remove() {} } };
  page.elements.viewport.listeners.pointerdown({ button: 0, clientX: 100, clientY: 100 });
  page.windowListeners.pointerup({});
  const text = { closest: (sel) => (sel === "[data-line]" ? group : null) };
  page.listeners.click({ target: text });
  assert.deepEqual(page.posted[1], { type: "reveal", line: 3, character: 4, endLine: 5, endCharacter: 5 });
  // A click outside any group posts nothing.
  page.listeners.click({ target: { closest: () => null } });
  assert.equal(page.posted.length, 2);

  page.windowListeners.message({ data: { type: "update", svg: "<svg>new</svg>" } });
  assert.equal(page.elements.diagram.innerHTML, "<svg>new</svg>");
  assert.equal(page.elements.status.hidden, true);
  page.windowListeners.message({ data: { type: "update", svg: "<svg>new</svg>", message: "no such element", stale: true } });
  assert.equal(page.elements.status.textContent, "no such element");
  assert.equal(page.elements.status.hidden, false);
  assert.ok(page.body.classList.has("stale"));
});

const WIDE = '<svg xmlns="http://www.w3.org/2000/svg" class="robosim-diagram" width="2000" height="500" viewBox="0 0 2000 500">' + SVG.slice(SVG.indexOf(">") + 1);

/** The transform the page set on the diagram, as numbers. */
function transform(page) {
  const m = page.elements.diagram.style.transform.match(/^translate\((-?[\d.e-]+)px, (-?[\d.e-]+)px\) scale\(([\d.e-]+)\)$/);
  assert.ok(m, `a translate and scale: ${page.elements.diagram.style.transform}`);
  return { x: Number(m[1]), y: Number(m[2]), scale: Number(m[3]) };
}

const close = (a, b, what) => assert.ok(Math.abs(a - b) < 1e-6, `${what}: ${a} is not ${b}`);

test("the view opens fitted to the window and follows the window's size", () => {
  const page = runPage(diagram.diagramHtml({ cspSource: "x", nonce: "n", title: "t", svg: WIDE }));
  // 2000 × 500 in 1000 × 800 with 12 px margins: the width decides.
  const t = transform(page);
  close(t.scale, 976 / 2000, "scale");
  close(t.x, 12, "x");
  close(t.y, (800 - 500 * t.scale) / 2, "y, centred");
  assert.equal(page.elements.zoom.textContent, "49%");
  assert.equal(page.view().fit, true);
  // A narrower window: fitted again.
  page.elements.viewport.clientWidth = 500;
  page.windowListeners.resize();
  close(transform(page).scale, 476 / 2000, "scale after the resize");
  // A small drawing is not blown up past twice its size.
  const small = runPage(diagram.diagramHtml({ cspSource: "x", nonce: "n", title: "t", svg: WIDE.replace('width="2000" height="500"', 'width="100" height="50"') }));
  close(transform(small).scale, 2, "scale of a small drawing");
});

test("the wheel zooms about the pointer, a drag pans, neither is a click; the Fit button fits again", () => {
  const page = runPage(diagram.diagramHtml({ cspSource: "x", nonce: "n", title: "t", svg: WIDE }));
  const before = transform(page);
  let prevented = false;
  // The pointer at (300, 200) in the viewport (its box starts at 10, 30).
  page.elements.viewport.listeners.wheel({ deltaY: -100, clientX: 310, clientY: 230, preventDefault: () => (prevented = true) });
  assert.ok(prevented, "the page does not scroll");
  const zoomed = transform(page);
  assert.ok(zoomed.scale > before.scale, "wheel up zooms in");
  // The drawing's point under the pointer stays under it.
  close((300 - zoomed.x) / zoomed.scale, (300 - before.x) / before.scale, "x under the pointer");
  close((200 - zoomed.y) / zoomed.scale, (200 - before.y) / before.scale, "y under the pointer");
  assert.equal(page.view().fit, false);

  // A drag moves the drawing by as much as the pointer.
  page.elements.viewport.listeners.pointerdown({ button: 0, clientX: 100, clientY: 100 });
  page.windowListeners.pointermove({ clientX: 160, clientY: 70 });
  assert.ok(page.elements.viewport.classList.has("dragging"));
  page.windowListeners.pointerup({});
  const panned = transform(page);
  close(panned.x, zoomed.x + 60, "x after the drag");
  close(panned.y, zoomed.y - 30, "y after the drag");
  close(panned.scale, zoomed.scale, "the drag keeps the zoom");
  // The click that ends a drag does not move the cursor.
  const group = { getAttribute: () => "1", classList: { add() {}, remove() {} } };
  page.listeners.click({ target: { closest: () => group } });
  assert.equal(page.posted.filter((m) => m.type === "reveal").length, 0);
  // A press that barely moves is still a click.
  page.elements.viewport.listeners.pointerdown({ button: 0, clientX: 100, clientY: 100 });
  page.windowListeners.pointermove({ clientX: 101, clientY: 101 });
  page.windowListeners.pointerup({});
  page.listeners.click({ target: { closest: () => group } });
  assert.equal(page.posted.filter((m) => m.type === "reveal").length, 1);
  close(transform(page).x, panned.x, "no pan below the threshold");

  // The buttons: in and out about the centre, then Fit.
  page.elements["zoom-in"].listeners.click();
  close(transform(page).scale, panned.scale * 1.25, "zoom in");
  page.elements["zoom-out"].listeners.click();
  close(transform(page).scale, panned.scale, "zoom out");
  page.elements.fit.listeners.click();
  close(transform(page).scale, before.scale, "fitted again");
  assert.equal(page.view().fit, true);
});

test("redraws after edits keep the zoom; a fitted view fits the new drawing; a reload restores the view", () => {
  const page = runPage(diagram.diagramHtml({ cspSource: "x", nonce: "n", title: "t", svg: WIDE }));
  page.elements.viewport.listeners.wheel({ deltaY: -200, clientX: 110, clientY: 130, preventDefault() {} });
  const zoomed = transform(page);
  // The edited model's drawing is larger: the zoom and position stay.
  const edited = WIDE.replace('width="2000" height="500"', 'width="2400" height="900"');
  page.windowListeners.message({ data: { type: "update", svg: edited } });
  assert.equal(page.elements.diagram.innerHTML, edited);
  assert.deepEqual(transform(page), zoomed);

  // Fitted: a redraw fits the new drawing.
  page.elements.fit.listeners.click();
  page.windowListeners.message({ data: { type: "update", svg: WIDE } });
  close(transform(page).scale, 976 / 2000, "fitted to the new drawing");
  page.windowListeners.message({ data: { type: "update", svg: edited } });
  close(transform(page).scale, Math.min(976 / 2400, 776 / 900), "fitted to the edited drawing");

  // The page is reloaded (hidden, then shown): the kept view is restored.
  const kept = { scale: 1.5, x: -40, y: 25, fit: false };
  const reloaded = runPage(diagram.diagramHtml({ cspSource: "x", nonce: "n", title: "t", svg: WIDE }), { state: kept });
  assert.deepEqual(transform(reloaded), { x: -40, y: 25, scale: 1.5 });
  assert.deepEqual(reloaded.view(), kept);
});

test("reveal messages: positions are checked, an end before the start is the start", () => {
  assert.deepEqual(diagram.parseReveal({ type: "reveal", line: 3, character: 4, endLine: 5, endCharacter: 1 }), {
    start: { line: 3, character: 4 },
    end: { line: 5, character: 1 },
  });
  assert.deepEqual(diagram.parseReveal({ type: "reveal", line: 3, character: 4, endLine: 2, endCharacter: 0 }), {
    start: { line: 3, character: 4 },
    end: { line: 3, character: 4 },
  });
  assert.deepEqual(diagram.parseReveal({ type: "reveal", line: 0, character: 0 }).end, { line: 0, character: 0 });
  for (const bad of [null, "reveal", { type: "ready" }, { type: "reveal", line: -1, character: 0 }, { type: "reveal", line: 1.5, character: 0 }, { type: "reveal", line: "1", character: 0 }]) {
    assert.equal(diagram.parseReveal(bad), undefined, JSON.stringify(bad));
  }
});

// --- the views -----------------------------------------------------------------

const URI = "file:///w/design.rct";

function result(name, svg = SVG) {
  return { uri: URI, diagrams: [{ model: { kind: "stateMachine", name, qualifiedName: `p::${name}` }, svg }] };
}

const wait = (ms) => new Promise((r) => setTimeout(r, ms));

function edit(languageId = "robochart") {
  for (const l of state.changeListeners) l({ document: { languageId, uri: { toString: () => URI } }, contentChanges: [{}] });
}

test("a lens opens a panel beside the editor with the SVG; edits refresh it once, after the delay", async () => {
  const requests = [];
  let svg = SVG;
  const views = new diagram.DiagramViews({
    request: async (uri, element) => {
      requests.push([uri, element]);
      return result("SMovement", svg);
    },
    languages: ["robochart", "robosim"],
    delay: 40,
  });
  state.activeTextEditor = { document: { uri: { toString: () => URI }, languageId: "robochart" }, viewColumn: 1 };
  await views.show(URI, "p::SMovement");
  assert.deepEqual(requests, [[URI, "p::SMovement"]]);
  assert.equal(state.panels.length, 1);
  const panel = state.panels[0];
  assert.equal(panel.viewType, "robosim.diagram");
  assert.equal(panel.title, "◇ SMovement");
  assert.equal(panel.showOptions.viewColumn, fakeVscode.ViewColumn.Beside);
  assert.equal(panel.options.enableScripts, true);
  assert.deepEqual(panel.options.localResourceRoots, []);
  assert.ok(panel.webview.html.includes(SVG));
  assert.ok(panel.webview.html.includes("vscode-webview://fake"));
  assert.deepEqual(views.open, [`${URI}\np::SMovement`]);

  // A burst of edits: one request, after the delay.
  svg = "<svg>edited</svg>";
  edit();
  edit();
  edit("robosim");
  edit("markdown"); // not a model
  await wait(10);
  assert.equal(requests.length, 1, "nothing before the delay");
  await wait(80);
  assert.equal(requests.length, 2, "one request for the burst");
  assert.deepEqual(panel.posted.at(-1), { type: "update", svg: "<svg>edited</svg>", message: undefined, stale: false });

  // A verification ends (its diagnostics change): the diagram is asked for
  // again, so that the counterexample the server draws shows.
  svg = "<svg>marked</svg>";
  for (const l of state.diagnosticListeners) l({ uris: [] });
  await wait(80);
  assert.equal(requests.length, 3, "one request after the diagnostics changed");
  assert.equal(panel.posted.at(-1).svg, "<svg>marked</svg>");
  svg = "<svg>edited</svg>";
  edit();
  await wait(80);

  // The page is reloaded (after being hidden): it gets the latest diagram.
  const before = panel.posted.length;
  panel.send({ type: "ready" });
  assert.equal(panel.posted.length, before + 1);
  assert.equal(panel.posted.at(-1).svg, "<svg>edited</svg>");

  // The same lens again: the same panel, revealed.
  await views.show(URI, "p::SMovement");
  assert.equal(state.panels.length, 1);
  assert.equal(panel.revealedTimes, 1);

  // Closing the panel forgets it.
  panel.dispose();
  assert.deepEqual(views.open, []);
  views.dispose();
});

test("an error keeps the last diagram, dimmed, with the server's message", async () => {
  let fail = false;
  const views = new diagram.DiagramViews({
    request: async () => {
      if (fail) throw new Error("no state machine, operation, controller or module named `p::S`");
      return result("S");
    },
    languages: ["robochart"],
    delay: 10,
  });
  await views.show(URI, "p::S");
  const panel = state.panels[0];
  fail = true;
  edit();
  await wait(50);
  assert.deepEqual(panel.posted.at(-1), {
    type: "update",
    svg: SVG,
    message: "no state machine, operation, controller or module named `p::S`",
    stale: true,
  });
  views.dispose();
});

test("a click in the diagram moves the cursor to the declaration in the source editor", async () => {
  const views = new diagram.DiagramViews({ request: async () => result("S"), languages: ["robochart"] });
  state.visibleTextEditors = [{ document: { uri: { toString: () => URI } }, viewColumn: 2 }];
  await views.show(URI, "p::S");
  const panel = state.panels[0];
  panel.send({ type: "reveal", line: 3, character: 4, endLine: 5, endCharacter: 5 });
  await wait(10);
  assert.equal(state.shown.length, 1);
  const { uri, options } = state.shown[0];
  assert.equal(uri, URI);
  assert.equal(options.viewColumn, 2, "the editor that shows the file");
  assert.equal(options.preserveFocus, false);
  assert.deepEqual(options.selection, new Range(new Position(3, 4), new Position(3, 4)), "the cursor at the start");
  assert.deepEqual(state.revealed, [
    {
      range: new Range(new Position(3, 4), new Position(5, 5)),
      type: fakeVscode.TextEditorRevealType.InCenterIfOutsideViewport,
    },
  ]);
  // Malformed messages are ignored.
  panel.send({ type: "reveal", line: "x" });
  panel.send({ type: "run", command: "rm -rf /" });
  await wait(10);
  assert.equal(state.shown.length, 1);
  views.dispose();
});

test("from the command palette: the active model's diagrams, one picked; errors are shown", async () => {
  const requests = [];
  const views = new diagram.DiagramViews({
    request: async (uri, element) => {
      requests.push([uri, element]);
      if (element === "Nowhere") throw new Error("no state machine named `Nowhere`");
      return {
        uri,
        diagrams: [result("A").diagrams[0], result("B").diagrams[0]],
      };
    },
    languages: ["robochart"],
  });
  // No model open.
  await views.show();
  assert.equal(state.infos.length, 1);
  state.activeTextEditor = { document: { uri: { toString: () => URI }, languageId: "robochart" }, viewColumn: 1 };
  await views.show();
  assert.deepEqual(requests, [[URI, undefined]]);
  assert.deepEqual(views.open, [`${URI}\np::B`], "the picked one (the stand-in picks the last)");
  await views.show(URI, "Nowhere");
  assert.deepEqual(state.errors, ["No diagram: no state machine named `Nowhere`"]);
  assert.equal(state.panels.length, 1);
  views.dispose();
});

test("package.json contributes the command to the palette for models only", () => {
  const pkg = JSON.parse(readFileSync(join(root, "package.json"), "utf8"));
  const cmd = pkg.contributes.commands.find((c) => c.command === "robosim.showDiagram");
  assert.ok(cmd, "robosim.showDiagram is contributed");
  assert.equal(cmd.category, "RoboSim");
  const palette = pkg.contributes.menus.commandPalette.find((m) => m.command === "robosim.showDiagram");
  assert.match(palette.when, /editorLangId == robochart/);
});
