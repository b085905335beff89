// Drives a real VS Code workbench (code-server, started by run.sh) with
// headless Chromium, as a person would: keyboard, mouse, and what the
// screen shows. Each step keeps a screenshot; a failed step says which one
// and the run goes on, so one regression does not hide the others.
// Prints `vscode-e2e: N passed, M failed` last; exits 1 if any step failed.
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";

const url = process.env.VSCODE_E2E_URL;
const workspace = process.env.VSCODE_E2E_WORKSPACE;
const shots = process.env.VSCODE_E2E_SHOTS;
const settingsFile = process.env.VSCODE_E2E_SETTINGS;
const nodeDir = process.env.VSCODE_E2E_NODE;
if (!url || !workspace || !shots || !settingsFile || !nodeDir) {
  console.error("test.mjs: run it through run.sh (VSCODE_E2E_* variables are unset)");
  process.exit(2);
}
// run.sh installs the packages outside editors/vscode (see there).
const { chromium } = createRequire(join(nodeDir, "package.json"))("playwright-core");

let passed = 0;
let failed = 0;
let shotNumber = 0;
let stepNumber = 0;
// VSCODE_E2E_ONLY=REGEX runs the first step and those whose names match.
const only = process.env.VSCODE_E2E_ONLY ? new RegExp(process.env.VSCODE_E2E_ONLY) : null;
const t0 = Date.now();

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu"],
});
const context = await browser.newContext({ viewport: { width: 1600, height: 1000 } });
const page = await context.newPage();
page.setDefaultTimeout(15000);
const browserLog = [];
page.on("console", (m) => browserLog.push(`${m.type()}: ${m.text()}`));

async function shot(name) {
  shotNumber += 1;
  const slug = name.toLowerCase().replace(/[^a-z0-9]+/g, "-").replace(/^-|-$/g, "");
  const file = join(shots, `${String(shotNumber).padStart(2, "0")}-${slug}.png`);
  try {
    await page.screenshot({ path: file });
  } catch (e) {
    console.log(`vscode-e2e: (no screenshot ${file}: ${e.message})`);
  }
  return file;
}

/** Runs one step with a time bound; its screenshot is kept either way. */
async function step(name, fn, seconds = 30) {
  if (only && !only.test(name) && shotNumber > 0) return; // while developing a step
  const started = Date.now();
  let timer;
  stepNumber += 1;
  try {
    await Promise.race([
      fn(),
      new Promise((_, reject) => {
        timer = setTimeout(() => reject(new Error(`no result after ${seconds} s`)), seconds * 1000);
      }),
    ]);
    const file = await shot(name);
    passed += 1;
    console.log(`vscode-e2e: ok ${name} (${((Date.now() - started) / 1000).toFixed(1)} s) ${file}`);
  } catch (e) {
    const file = await shot(`FAILED-${name}`);
    failed += 1;
    console.log(`vscode-e2e: FAIL ${name}: ${e.message.split("\n")[0]}`);
    console.log(`vscode-e2e:   screenshot ${file}`);
  } finally {
    clearTimeout(timer);
    stepNumber += 1; // stops the polls of a step that ran out of time
  }
}

/** Ends a probe that did not find what it wants, saying what it saw. */
function seen(what) {
  throw new Error(typeof what === "string" ? what : JSON.stringify(what));
}

/** Polls `probe` until it returns a truthy value; throws `what` after `ms`. */
async function until(what, probe, ms = 15000) {
  const end = Date.now() + ms;
  const mine = stepNumber;
  let last;
  for (;;) {
    if (stepNumber !== mine) throw new Error(`${what}: abandoned (the step ran out of time)`);
    try {
      last = await probe();
      if (last) return last;
    } catch (e) {
      last = e.message;
    }
    if (Date.now() > end) throw new Error(`${what} (last seen: ${JSON.stringify(last)?.slice(0, 300)})`);
    await page.waitForTimeout(200);
  }
}

const statusText = async (id) => {
  const el = page.locator(`[id="${id}"]`);
  return (await el.count()) ? (await el.first().innerText()).trim() : "";
};
const cursor = () => statusText("status.editor.selection");
const languageMode = () => statusText("status.editor.mode");
const activeEditor = () => page.locator(".editor-group-container.active .monaco-editor").first();

/** Runs a command from the Command Palette (F1), by its title. */
async function command(title) {
  await page.keyboard.press("F1");
  const input = page.locator(".quick-input-widget input");
  await input.waitFor({ state: "visible" });
  await input.fill(`>${title}`);
  // As in openFile: Enter only once the list has filtered down to it.
  const first = page.locator(".quick-input-list .monaco-list-row").first();
  await until(`the command palette offers ${title} first`, async () => {
    const label = (await first.getAttribute("aria-label")) ?? "";
    return label.startsWith(title) ? label : seen(label);
  });
  await page.keyboard.press("Enter");
}

/** Opens a workspace file with Quick Open (Ctrl+P). */
async function openFile(rel) {
  const name = rel.split("/").pop();
  const folder = rel.includes("/") ? rel.slice(0, rel.lastIndexOf("/")) : "";
  await page.keyboard.press("Escape");
  await page.keyboard.press("Control+P");
  const input = page.locator(".quick-input-widget input");
  await input.waitFor({ state: "visible" });
  await input.fill(rel);
  // The list filters as it is typed: Enter only once the first row is the file.
  const first = page.locator(".quick-input-list .monaco-list-row").first();
  await until(`quick open offers ${rel} first`, async () => {
    const label = (await first.getAttribute("aria-label")) ?? "";
    return label.startsWith(name) && label.includes(folder) ? label : seen(label);
  });
  await page.keyboard.press("Enter");
  await until(`${name} is the active editor`, async () => {
    const tab = page.locator(".editor-group-container.active .tab.active");
    return (await tab.count()) && (await tab.first().getAttribute("aria-label"))?.startsWith(name);
  });
}

/** Moves the cursor with Go to Line (1-based line and column). */
async function goTo(line, column) {
  await page.keyboard.press("Escape");
  await page.keyboard.press("Control+G");
  const input = page.locator(".quick-input-widget input");
  await input.waitFor({ state: "visible" });
  await input.fill(`:${line}:${column}`);
  await page.locator(".quick-input-list .monaco-list-row", { hasText: `Go to line ${line} and character ${column}` }).first().waitFor();
  await page.keyboard.press("Enter");
  await until(`the cursor at ${line}:${column}`, async () => {
    const c = await cursor();
    return c.startsWith(`Ln ${line}, Col ${column}`) ? c : seen(c);
  });
}

/** The 1-based line and column of the first `needle` in a workspace file. */
function find(rel, needle, offset = 0) {
  const text = readFileSync(join(workspace, rel), "utf8");
  const i = text.indexOf(needle);
  if (i < 0) throw new Error(`${needle} not in ${rel}`);
  const before = text.slice(0, i + offset).split("\n");
  return [before.length, before[before.length - 1].length + 1];
}

/** The text of the hover on screen ("" when there is none). */
async function hoverText() {
  const hover = page.locator(".monaco-hover:not(.hidden) .monaco-hover-content");
  if (!(await hover.count())) return "";
  return (await hover.allInnerTexts()).join("\n");
}

/** Scrolls the hover to the paragraph that contains `text`, for the screenshot. */
async function revealInHover(text) {
  await page.evaluate((t) => {
    const hover = document.querySelector(".monaco-hover:not(.hidden) .monaco-hover-content");
    if (!hover) return;
    const all = [...hover.querySelectorAll("p, li, code, span, div")].filter((e) => e.textContent.includes(t));
    const deepest = all.find((e) => ![...e.children].some((c) => c.textContent.includes(t))) ?? all[0];
    deepest?.scrollIntoView({ block: "center" });
  }, text);
  await page.waitForTimeout(200);
}

/** Shows the hover at the cursor (Show or Focus Hover, Ctrl+K Ctrl+I). */
async function hoverAtCursor(expect, ms = 15000) {
  return until(`a hover containing ${JSON.stringify(expect)}`, async () => {
    const t = await hoverText();
    if (t.includes(expect)) return t;
    await page.keyboard.press("Escape");
    await page.keyboard.press("Control+K");
    await page.keyboard.press("Control+I");
    await page.waitForTimeout(400);
    const u = await hoverText();
    return u.includes(expect) ? u : false;
  }, ms);
}

const oneLine = (t) => t.replace(/\s+/g, " ").slice(0, 200);

/** The box of line `line`'s number in the gutter of the active editor. */
async function lineBox(line) {
  const n = activeEditor().locator(".margin-view-overlays .line-numbers", { hasText: new RegExp(`^\\s*${line}\\s*$`) });
  return (await n.count()) ? n.first().boundingBox() : null;
}

/** An error squiggle on line `line` of the active editor, once drawn. */
async function squiggleOnLine(line) {
  const box = await lineBox(line);
  if (!box) return null;
  const all = activeEditor().locator(".squiggly-error");
  for (let i = 0; i < (await all.count()); i++) {
    const b = await all.nth(i).boundingBox();
    if (b && b.y + b.height / 2 > box.y && b.y + b.height / 2 < box.y + box.height) return all.nth(i);
  }
  return null;
}

/** The code lens whose text starts with `prefix` just above line `line`. */
async function lensAbove(line, prefix) {
  const box = await lineBox(line);
  if (!box) return null;
  const all = activeEditor().locator(".codelens-decoration a");
  for (let i = 0; i < (await all.count()); i++) {
    const b = await all.nth(i).boundingBox();
    const t = await all.nth(i).innerText();
    if (b && t.startsWith(prefix) && b.y < box.y && b.y > box.y - 2 * box.height) return all.nth(i);
  }
  return null;
}

// The workspace's files as run.sh copied them, before any edit.
const original = { "paper/design.rct": readFileSync(join(workspace, "paper/design.rct"), "utf8") };

try {
  await step("workbench loads", async () => {
    await page.goto(url);
    await page.locator(".monaco-workbench").waitFor({ timeout: 60000 });
    await page.locator(".explorer-folders-view, .explorer-viewlet").first().waitFor({ timeout: 60000 });
  }, 90);

  // Problems panel: the codes of the known violations (violations.rct), and
  // no others in the whole workspace.
  await step("problems panel codes", async () => {
    await openFile("violations.rct");
    await until("RoboChart is the language mode", async () => (await languageMode()) === "RoboChart");
    await command("View: Focus Problems");
    const panel = page.locator(".markers-panel");
    await panel.waitFor();
    const want = ["RC:IJ2", "RC:STM3", "RC:STM4", "RC:TE4"];
    const codes = await until(`the Problems panel lists exactly ${want.join(", ")}`, async () => {
      const t = await panel.innerText();
      // The row reads `robosim` then the code (the brackets are CSS).
      const found = [...t.matchAll(/robosim\s*\(?\s*([A-Z]+[-:][^\s)]+)/g)].map((m) => m[1]).sort();
      return found.join(",") === want.join(",") ? found : seen(t);
    }, 30000);
    console.log(`vscode-e2e:   codes: ${codes.join(" ")}`);
  }, 60);

  await step("squiggle and its hover", async () => {
    await openFile("violations.rct");
    const [line, column] = find("violations.rct", "> true", 2);
    await goTo(line, column);
    const squiggle = await until(`an error squiggle on line ${line}`, () => squiggleOnLine(line));
    // The editor may still be scrolling: wait until the squiggle stops moving.
    let box = await squiggle.boundingBox();
    await until("the squiggle stops moving", async () => {
      await page.waitForTimeout(300);
      const b = await squiggle.boundingBox();
      const still = b && box && Math.abs(b.x - box.x) < 1 && Math.abs(b.y - box.y) < 1;
      box = b ?? box;
      return still;
    });
    const text = await until("the squiggle's hover shows RC:TE4 and its message", async () => {
      const b = await squiggle.boundingBox();
      await page.mouse.move(b.x + b.width / 2 - 3, b.y + b.height / 2 - 2);
      await page.mouse.move(b.x + b.width / 2, b.y + b.height / 2);
      await page.waitForTimeout(800);
      const t = await hoverText();
      return t.includes("RC:TE4") && t.includes("a timed expression is compared with a number") ? t : false;
    }, 20000);
    console.log(`vscode-e2e:   hover: ${oneLine(text)}`);
  }, 45);

  // A use of a machine: the hover shows its declaration and its comment.
  await step("hover shows the declaration", async () => {
    await openFile("paper/design.rct");
    const [line, column] = find("paper/design.rct", "sref sm = SMovement", 10);
    await goTo(line, column + 2);
    const text = await hoverAtCursor("stm SMovement");
    if (!text.includes("Move forward; on an obstacle, stop and turn")) throw new Error(`no doc comment: ${oneLine(text)}`);
    console.log(`vscode-e2e:   hover: ${oneLine(text)}`);
  });

  // A csp block of an assertion file: the hover of a library process, then
  // a name nothing defines, typed into the block, gets its squiggle and the
  // CSPm engine's diagnostic as the text changes (the file is reverted).
  await step("csp block: library hover, squiggle and its hover", async () => {
    await openFile("csp.assertions");
    await until("RoboChart Assertions is the language mode", async () => (await languageMode()) === "RoboChart Assertions");
    const [line, column] = find("csp.assertions", "StartBy(");
    await goTo(line, column + 2);
    const hover = await hoverAtCursor("must perform its first event within");
    console.log(`vscode-e2e:   hover: ${oneLine(hover)}`);
    const [l2, c2] = find("csp.assertions", "; Spec", 2);
    await goTo(l2, c2);
    await page.keyboard.press("Escape");
    await page.keyboard.press("Shift+End");
    await page.keyboard.type("Undefined");
    const squiggle = await until(`an error squiggle on line ${l2}`, () => squiggleOnLine(l2), 20000);
    const text = await until("the squiggle's hover shows CSP-N01 and its message", async () => {
      const b = await squiggle.boundingBox();
      await page.mouse.move(b.x + b.width / 2 - 3, b.y + b.height / 2 - 2);
      await page.mouse.move(b.x + b.width / 2, b.y + b.height / 2);
      await page.waitForTimeout(800);
      const t = await hoverText();
      return t.includes("CSP-N01") && t.includes("`Undefined` is not defined") ? t : false;
    }, 20000);
    console.log(`vscode-e2e:   squiggle hover: ${oneLine(text)}`);
    await shot("csp-block-squiggle");
    await command("File: Revert File");
    await until("the squiggle goes away with the revert", async () => !(await squiggleOnLine(l2)));
    // And the Problems panel (updated apart from the editor) drops it too:
    // no stale CSP-N01 once the text is back.
    await until("the Problems panel drops CSP-N01 with the revert", async () => {
      const t = await page.locator(".markers-panel").innerText().catch(() => "");
      return !t.includes("CSP-N01");
    }, 20000);
  }, 60);

  // From a RoboSim file to the interface it imports from another file.
  await step("go to definition across files", async () => {
    await openFile("paper/simulation_alt.rst");
    const [line, column] = find("paper/simulation_alt.rst", "requires MovementI", 9);
    await until("RoboSim is the language mode", async () => (await languageMode()) === "RoboSim");
    await goTo(line, column + 2);
    await page.keyboard.press("F12");
    const [declLine] = find("paper/simulation.rst", "interface MovementI");
    await until("simulation.rst is the active editor", async () =>
      (await page.locator(".editor-group-container.active .tab.active").first().getAttribute("aria-label"))?.startsWith("simulation.rst"),
    );
    await until(`the cursor on line ${declLine} of simulation.rst`, async () => (await cursor()).startsWith(`Ln ${declLine},`));
  });

  await step("completion", async () => {
    await openFile("paper/design.rct");
    const [line, column] = find("paper/design.rct", "sref sm = SMovement", 13);
    await goTo(line, column); // after `SMo`
    await page.keyboard.press("Shift+End");
    await page.keyboard.press("Delete");
    await page.keyboard.press("Control+Space");
    const rows = page.locator(".editor-widget.suggest-widget.visible .monaco-list-row");
    const labels = await until("the suggestions include SMovement", async () => {
      const l = await rows.evaluateAll((rs) => rs.map((r) => r.getAttribute("aria-label") ?? ""));
      return l.some((x) => x.startsWith("SMovement")) ? l : false;
    });
    console.log(`vscode-e2e:   suggestions: ${labels.slice(0, 6).map((l) => l.split(",")[0]).join(" | ")}`);
    await shot("completion-list");
    await page.locator(".editor-widget.suggest-widget.visible .monaco-list-row", { hasText: "SMovement" }).first().click();
    await page.keyboard.press("Control+S");
    await until("the accepted completion restores `sref sm = SMovement` on disk", async () =>
      readFileSync(join(workspace, "paper/design.rct"), "utf8") === original["paper/design.rct"],
    );
  });

  await step("format document", async () => {
    await openFile("unformatted.rct");
    await command("Format Document");
    await until("the document is edited", async () =>
      (await page.locator(".editor-group-container.active .tab.active.dirty").count()) > 0);
    await page.keyboard.press("Control+S");
    const want = readFileSync(new URL("./expected/unformatted.rct", import.meta.url), "utf8");
    await until("unformatted.rct on disk is formatted", async () =>
      readFileSync(join(workspace, "unformatted.rct"), "utf8") === want,
    );
  });

  await step("outline", async () => {
    await openFile("paper/design.rct");
    await command("Explorer: Focus on Outline View");
    // Give the outline the Explorer's height: fold the folder view.
    const folders = page.locator(".explorer-viewlet .pane-header[aria-expanded='true']", { hasText: /workspace/i });
    if (await folders.count()) await folders.first().click();
    const pane = page.locator(".pane", { has: page.locator(".pane-header", { hasText: /^\s*Outline/i }) });
    const want = ["paper_design", "MovementI", "move", "stop", "ObstacleI", "obstacle", "SMovement", "Moving", "Turning", "Movement", "CFootBot"];
    const names = await until(`the outline lists ${want.join(", ")}`, async () => {
      const rows = await pane.locator(".monaco-list-row .label-name").allInnerTexts();
      const n = rows.map((x) => x.trim());
      return want.every((w) => n.includes(w)) ? n : seen(n);
    });
    console.log(`vscode-e2e:   outline: ${names.join(" ")}`);
    await shot("outline-view");
    // Back to the folder view for the steps after.
    const folded = page.locator(".explorer-viewlet .pane-header[aria-expanded='false']", { hasText: /workspace/i });
    if (await folded.count()) await folded.first().click();
  });

  await step("rst: reStructuredText stays reStructuredText", async () => {
    await openFile("notes.rst");
    await until("reStructuredText is the language mode", async () => (await languageMode()) === "reStructuredText");
    // The extension decides when the document opens; give it time to (wrongly) switch.
    await page.waitForTimeout(2000);
    const mode = await languageMode();
    if (mode !== "reStructuredText") throw new Error(`notes.rst switched to ${mode}`);
    // Nor does the server check it.
    await command("View: Focus Problems");
    const problems = await page.locator(".markers-panel").innerText();
    if (problems.includes("notes.rst")) throw new Error(`notes.rst has problems: ${oneLine(problems)}`);
  });

  await step("rst: a RoboSim model opens as RoboSim", async () => {
    await openFile("paper/simulation.rst");
    await until("RoboSim is the language mode", async () => (await languageMode()) === "RoboSim");
  });

  await step("verify lens: progress and verdict", async () => {
    await openFile("big/big.rsa");
    const [line] = find("big/big.rsa", "assertion Large");
    await goTo(line, 1);
    const lens = await until("a ▶ Verify lens above `assertion Large`", () => lensAbove(line, "▶ Verify"));
    // LSP work-done progress is a silent notification: its title in the
    // status bar, and the notification in the list (opened beforehand, so
    // that nothing depends on how long the check takes).
    await command("Notifications: Show Notifications");
    await page.locator(".notifications-center").waitFor();
    await lens.click();
    const status = page.locator('[id="status.progress"]');
    const item = page.locator(".notifications-center .notification-list-item", { hasText: "Verifying assertion Large" });
    let sawStatus = "";
    let sawItem = "";
    await until("the check's progress in the status bar and the notification list", async () => {
      if (!sawStatus && (await status.count())) {
        const t = await status.first().innerText();
        if (t.includes("Verifying assertion Large")) sawStatus = t;
      }
      if (!sawItem && (await item.count())) sawItem = await item.first().innerText();
      if (sawStatus && sawItem) return true;
      if (await lensAbove(line, "✔ pass")) seen(`finished first; status bar: ${JSON.stringify(sawStatus)}, list: ${JSON.stringify(sawItem)}`);
      return seen(`status bar: ${JSON.stringify(sawStatus)}, list: ${JSON.stringify(sawItem)}`);
    }, 30000);
    await shot("verify-progress");
    console.log(`vscode-e2e:   progress: ${oneLine(sawItem)}`);
    const done = await until("the lens shows the verdict ✔ pass", () => lensAbove(line, "✔ pass"), 90000);
    console.log(`vscode-e2e:   lens: ${await done.innerText()}`);
    await page.keyboard.press("Escape"); // hides the notification list
  }, 120);

  await step("verify lens: a failing check", async () => {
    await openFile("failing.rsa");
    const [line, column] = find("failing.rsa", "assertion Fails", 10);
    await goTo(line, 1);
    const lens = await until("a ▶ Verify lens above `assertion Fails`", () => lensAbove(line, "▶ Verify"));
    await lens.click();
    await until("the lens shows ✘ fail", () => lensAbove(line, "✘ fail"), 60000);
    await command("View: Focus Problems");
    await until("the Problems panel shows the failure on failing.rsa", async () =>
      (await page.locator(".markers-panel").innerText()).includes("CFootBot cannot be scheduled in cycles of period 2"));
    await goTo(line, column + 1);
    const text = await hoverAtCursor("fail · 28 states");
    if (!text.includes("robotool3")) throw new Error(`the hover does not name the semantics: ${oneLine(text)}`);
    await revealInHover("fail · 28 states");
    console.log(`vscode-e2e:   hover: ${oneLine(text.slice(text.indexOf("fail · 28 states")))}`);
  }, 90);

  await step("diagram webview and a click", async () => {
    await openFile("paper/design.rct");
    const [line] = find("paper/design.rct", "stm SMovement");
    await goTo(line, 1);
    const lens = await until("a ◇ Show diagram lens above `stm SMovement`", () => lensAbove(line, "◇ Show diagram"));
    await lens.click();
    const frame = page.frameLocator("iframe.webview.ready").frameLocator("#active-frame");
    const svg = frame.locator("svg").first();
    await svg.waitFor({ timeout: 20000 });
    const texts = await until("the diagram shows Moving and Turning", async () => {
      const t = await svg.locator("text").evaluateAll((ts) => ts.map((x) => (x.textContent ?? "").trim()));
      return t.includes("Moving") && t.includes("Turning") ? t : seen(t);
    });
    console.log(`vscode-e2e:   diagram texts: ${texts.slice(0, 12).join(" | ")}`);
    await shot("diagram");
    await frame.locator("svg text", { hasText: /^Turning$/ }).first().click();
    const [turning] = find("paper/design.rct", "state Turning");
    await until(`the cursor moves to line ${turning} (state Turning)`, async () => (await cursor()).startsWith(`Ln ${turning},`));
  }, 60);

  await step("setting robosim.verify.semantics takes effect", async () => {
    await command("Preferences: Open User Settings");
    const search = page.locator(".settings-editor .suggest-input-container .monaco-editor textarea, .settings-editor .search-container textarea").first();
    await search.waitFor();
    await search.fill("robosim.verify.semantics");
    const select = page.locator(".settings-editor .setting-item-contents select").first();
    await until("the setting robosim.verify.semantics is shown", async () =>
      (await page.locator(".settings-editor .setting-item-title").allInnerTexts()).join("|").includes("Verify: Semantics"));
    await select.click();
    await page.locator(".monaco-select-box-dropdown-container .option-text", { hasText: /^paper2019$/ }).click();
    await until("settings.json has paper2019", async () =>
      readFileSync(settingsFile, "utf8").includes('"robosim.verify.semantics": "paper2019"'));
    await shot("settings");
    await openFile("failing.rsa");
    const [line, column] = find("failing.rsa", "assertion Fails", 10);
    await goTo(line, 1);
    const lens = await until("the lens above `assertion Fails`", () => lensAbove(line, "✘ fail"));
    await lens.click();
    await goTo(line, column + 1);
    const text = await hoverAtCursor("paper2019", 30000);
    if (!text.includes("fail · 39 states")) throw new Error(`not the paper's counterexample: ${oneLine(text)}`);
    await revealInHover("fail · 39 states");
    console.log(`vscode-e2e:   hover: ${oneLine(text.slice(text.indexOf("fail · 39 states")))}`);
  }, 90);
} finally {
  const elapsed = ((Date.now() - t0) / 1000).toFixed(1);
  if (failed > 0) {
    console.log("vscode-e2e: last browser console messages:");
    for (const m of browserLog.slice(-15)) console.log(`  ${m.slice(0, 300)}`);
  }
  await browser.close().catch(() => {});
  console.log(`vscode-e2e: ${elapsed} s in the workbench`);
  console.log(`vscode-e2e: ${passed} passed, ${failed} failed`);
  process.exitCode = failed > 0 ? 1 : 0;
}
