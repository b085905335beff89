// `.rst` is both RoboSim and reStructuredText. VS Code gives `.rst` files to
// its reStructuredText language; this module decides, from a file's content
// and the user's `files.associations`, whether to switch one to RoboSim. No
// `vscode` import here, so the tests run it in plain Node. The Neovim plugin
// (editors/neovim/lua/robosim/filetype.lua) implements the same rule.

/** Lines looked at; the rest of a large file is ignored. */
export const MAX_LINES = 5000;

const NAME = String.raw`\^?[A-Za-z_][A-Za-z0-9_]*`;
const QUALIFIED = `${NAME}(?:::${NAME})*`;

/**
 * The first line (outside comments) of a RoboChart or RoboSim file: a
 * declaration keyword, a name, then the end of the line or `{`/`(`.
 */
const DECLARATION = new RegExp(
  "^\\s*(?:" +
    [
      `package\\s+${QUALIFIED}\\s*$`,
      `import\\s+${QUALIFIED}(?:::\\*)?\\s*$`,
      `(?:type|diagram)\\s+${NAME}\\s*$`,
      `(?:interface|datatype|record|enumeration|controller|stm|module)\\s+${NAME}\\s*(?:\\{.*)?$`,
      `robotic\\s+platform\\s+${NAME}\\s*(?:\\{.*)?$`,
      `(?:operation|function)\\s+${NAME}\\s*(?:[({].*)?$`,
    ].join("|") +
    ")",
);

/**
 * A line that only reStructuredText would have: an explicit markup start
 * (`.. note::`, `.. _label:`, `..` comments) or a section adornment (three or
 * more of one of `= - ~ ^ * # +`). The same test as the command line's
 * folder search (`looks_like_restructured_text` in crates/ide).
 */
export function isRestructuredTextLine(line: string): boolean {
  const t = line.trimEnd();
  if (t.startsWith(".. ") || t === "..") return true;
  return t.length >= 3 && /^([=\-~^*#+])\1+$/.test(t);
}

/**
 * The text with `//` and `/* … *\/` comments replaced by spaces (line breaks
 * are kept), at most `MAX_LINES` lines. Strings are not special-cased: a `//`
 * inside a string only hides the rest of its line, which does not change the
 * verdict below.
 */
export function stripComments(text: string): string[] {
  const lines = text.split(/\r\n|\r|\n/, MAX_LINES);
  const out: string[] = [];
  let inBlock = false;
  for (const line of lines) {
    let kept = "";
    let i = 0;
    while (i < line.length) {
      if (inBlock) {
        const end = line.indexOf("*/", i);
        if (end < 0) {
          i = line.length;
        } else {
          kept += " ";
          i = end + 2;
          inBlock = false;
        }
      } else if (line.startsWith("/*", i)) {
        inBlock = true;
        i += 2;
      } else if (line.startsWith("//", i)) {
        i = line.length;
      } else {
        kept += line[i];
        i += 1;
      }
    }
    out.push(kept);
  }
  return out;
}

/**
 * Whether a `.rst` file's text is RoboSim: its first non-blank line outside
 * comments is a declaration (`package x`, `import a::b`, `stm S {`, …), and
 * no line outside comments looks like reStructuredText markup.
 */
export function looksLikeRoboSim(text: string): boolean {
  const code = stripComments(text.startsWith("\uFEFF") ? text.slice(1) : text);
  const first = code.find((l) => l.trim() !== "");
  if (first === undefined || !DECLARATION.test(first)) return false;
  return !code.some(isRestructuredTextLine);
}

/**
 * A glob of `files.associations` as a regular expression, with VS Code's
 * syntax: `*`, `?`, `**`, `{a,b}` and `[…]`, case-insensitive.
 */
export function globToRegExp(glob: string): RegExp {
  let re = "";
  let i = 0;
  let inBraces = false;
  while (i < glob.length) {
    const c = glob[i];
    if (c === "*") {
      if (glob[i + 1] === "*") {
        // `**/` is any number of folders, `**` anything.
        if (glob[i + 2] === "/") {
          re += "(?:.*/)?";
          i += 3;
        } else {
          re += ".*";
          i += 2;
        }
      } else {
        re += "[^/]*";
        i += 1;
      }
    } else if (c === "?") {
      re += "[^/]";
      i += 1;
    } else if (c === "{" && !inBraces) {
      re += "(?:";
      inBraces = true;
      i += 1;
    } else if (c === "}" && inBraces) {
      re += ")";
      inBraces = false;
      i += 1;
    } else if (c === "," && inBraces) {
      re += "|";
      i += 1;
    } else if (c === "[") {
      const end = glob.indexOf("]", i + 1);
      if (end < 0) {
        re += "\\[";
        i += 1;
      } else {
        let body = glob.slice(i + 1, end);
        if (body.startsWith("!")) body = "^" + body.slice(1);
        re += "[" + body.replace(/\\/g, "\\\\") + "]";
        i = end + 1;
      }
    } else {
      re += c.replace(/[.+^$|()\\\]{}]/g, "\\$&");
      i += 1;
    }
  }
  if (inBraces) re += ")";
  return new RegExp("^" + re + "$", "i");
}

/**
 * The language a user's `files.associations` gives `fsPath`, if one of its
 * patterns matches: the longest matching pattern wins, as in VS Code. A
 * pattern without `/` is matched against the file name, one with `/` against
 * the whole path.
 */
export function userAssociation(
  fsPath: string,
  associations: Record<string, unknown> | undefined,
): string | undefined {
  if (!associations) return undefined;
  const full = fsPath.replace(/\\/g, "/");
  const base = full.slice(full.lastIndexOf("/") + 1);
  let best: { pattern: string; language: string } | undefined;
  for (const [pattern, language] of Object.entries(associations)) {
    if (typeof language !== "string" || language === "") continue;
    const target = pattern.includes("/") ? full : base;
    let matches: boolean;
    try {
      matches = globToRegExp(pattern).test(target);
    } catch {
      matches = false;
    }
    if (matches && (!best || pattern.length > best.pattern.length)) best = { pattern, language };
  }
  return best?.language;
}

export function isRstPath(fsPath: string): boolean {
  return /\.rst$/i.test(fsPath);
}

/** Languages a `.rst` file may have been given that we may switch from. */
export const SWITCHABLE_LANGUAGES: readonly string[] = ["restructuredtext", "plaintext"];

export interface OpenedDocument {
  uri: string;
  fsPath: string;
  languageId: string;
  text: string;
  /** `robosim.rst.detect` for this document. */
  detect: boolean;
  /** The effective `files.associations`. */
  associations?: Record<string, unknown>;
}

/**
 * The decisions taken as documents open and close. VS Code reports a change
 * of language as a close then an open of the same URI; when a RoboSim
 * document is reopened at once in another language, someone chose that
 * language (the Change Language Mode picker, or another extension), and the
 * choice is kept for the rest of the session.
 */
export class RstSwitcher {
  private readonly closedAsRoboSim = new Map<string, number>();
  private readonly chosen = new Set<string>();

  constructor(private readonly changeWindowMs = 1500) {}

  onDidClose(uri: string, languageId: string, now: number): void {
    if (languageId === "robosim") this.closedAsRoboSim.set(uri, now);
  }

  /** Whether a document that just opened should become RoboSim. */
  shouldSwitch(doc: OpenedDocument, now: number): boolean {
    if (!isRstPath(doc.fsPath) || !SWITCHABLE_LANGUAGES.includes(doc.languageId)) return false;
    const closed = this.closedAsRoboSim.get(doc.uri);
    this.closedAsRoboSim.delete(doc.uri);
    if (closed !== undefined && now - closed <= this.changeWindowMs) this.chosen.add(doc.uri);
    if (this.chosen.has(doc.uri) || !doc.detect) return false;
    if (userAssociation(doc.fsPath, doc.associations) !== undefined) return false;
    return looksLikeRoboSim(doc.text);
  }
}
