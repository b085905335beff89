// The CSPm embedded in the `csp-begin … csp-end` blocks of assertion files,
// for generate.mjs. As for the model languages, spellings are not written
// here: keywords and punctuation are read from the CSPm lexer's table
// (crates/cspm/src/kinds.rs), and the names of FDR's and RoboTool's library
// from crates/hir/src/csp_library.rs (the table hovers and completion use).
//
// A block ends at the first `csp-end`, wherever it is (even inside a CSP
// comment or string), so no rule here can run past a `csp-end`: single
// matches stop before one, and the block comment's end also stops there.

import fs from 'node:fs';
import path from 'node:path';

const NOT_END = '(?!csp-end)';
const IDENT = `[A-Za-z_](?:${NOT_END}[A-Za-z0-9_])*'*`;
const START = "(?<![A-Za-z0-9_'])";
const END = "(?![A-Za-z0-9_'])";

const KEYWORD_SCOPES = {
  'storage.type': [
    'channel', 'datatype', 'subtype', 'nametype', 'module', 'exports', 'endmodule', 'instance',
    'external', 'transparent',
  ],
  'keyword.control.conditional': ['if', 'then', 'else'],
  'keyword.other.binder': ['let', 'within'],
  'keyword.operator.word': ['and', 'or', 'not'],
  'constant.language.boolean': ['true', 'false'],
  'keyword.other.assert': ['assert'],
  'keyword.other.timed': ['Timed'],
};

// Punctuation by token kind; the rest are process operators.
const PUNCT_SCOPES = {
  L_PAREN: 'punctuation.section.parens.begin',
  R_PAREN: 'punctuation.section.parens.end',
  L_BRACE: 'punctuation.section.braces.begin',
  R_BRACE: 'punctuation.section.braces.end',
  L_PIPE_BRACE: 'punctuation.section.closure.begin',
  R_PIPE_BRACE: 'punctuation.section.closure.end',
  L_BRACK: 'punctuation.section.brackets.begin',
  R_BRACK: 'punctuation.section.brackets.end',
  COMMA: 'punctuation.separator.comma',
  COLON2: 'punctuation.separator.namespace',
  COLON: 'punctuation.separator.colon',
  AT: 'punctuation.separator.at',
  PIPE: 'punctuation.separator.pipe',
  DOT: 'keyword.operator.dot',
  DOT2: 'keyword.operator.range',
  QUESTION: 'keyword.operator.input',
  BANG: 'keyword.operator.output',
  DOLLAR: 'keyword.operator.nondeterministic-input',
  ARROW: 'keyword.operator.arrow',
  DRAWN: 'keyword.operator.generator',
  EQ: 'keyword.operator.assignment',
  EQ2: 'keyword.operator.comparison',
  NEQ: 'keyword.operator.comparison',
  LT: 'keyword.operator.comparison',
  GT: 'keyword.operator.comparison',
  LTEQ: 'keyword.operator.comparison',
  GTEQ: 'keyword.operator.comparison',
  PLUS: 'keyword.operator.arithmetic',
  MINUS: 'keyword.operator.arithmetic',
  STAR: 'keyword.operator.arithmetic',
  SLASH: 'keyword.operator.arithmetic',
  PERCENT: 'keyword.operator.arithmetic',
  CARET: 'keyword.operator.concatenation',
  HASH: 'keyword.operator.length',
  UNDERSCORE: 'variable.language.wildcard',
  REFINES_T: 'keyword.operator.refinement',
  REFINES_F: 'keyword.operator.refinement',
  REFINES_FD: 'keyword.operator.refinement',
  REFINES_V: 'keyword.operator.refinement',
  REFINES_VD: 'keyword.operator.refinement',
  REFINES_R: 'keyword.operator.refinement',
  REFINES_RD: 'keyword.operator.refinement',
  PROP_OPEN: 'keyword.operator.refinement',
};
const DEFAULT_PUNCT = 'keyword.operator.process';

// Library names by the kind csp_library.rs gives them.
const LIBRARY_SCOPES = { P: 'support.function.process', F: 'support.function', T: 'support.type', Ch: 'support.constant', Ctor: 'support.constant' };

const escapeRe = (s) => s.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
const longestFirst = (xs) => [...xs].sort((a, b) => b.length - a.length || a.localeCompare(b));

function readTables(root) {
  const kinds = fs.readFileSync(path.join(root, 'crates', 'cspm', 'src', 'kinds.rs'), 'utf8');
  const block = (name) => {
    const m = new RegExp(`^\\s*${name}\\s*\\{\\n([\\s\\S]*?)^\\s*\\}`, 'm').exec(kinds);
    if (!m) throw new Error(`cspm kinds.rs: no \`${name} { … }\` block found`);
    return m[1];
  };
  const unescape = (s) => s.replace(/\\(.)/g, '$1');
  const pairs = (text) => [...text.matchAll(/([A-Z0-9_]+)\s*=\s*"((?:[^"\\]|\\.)*)"/g)].map((m) => ({ kind: m[1], text: unescape(m[2]) }));
  const keywords = pairs(block('keywords'));
  const punct = pairs(block('punct'));
  const lib = fs.readFileSync(path.join(root, 'crates', 'hir', 'src', 'csp_library.rs'), 'utf8');
  const library = [...lib.matchAll(/^\s*(?:Fdr|RoboTool) (P|F|T|Ch|Ctor) "([^"]+)"/gm)].map((m) => ({ kind: m[1], name: m[2] }));
  if (keywords.length < 20 || punct.length < 40 || library.length < 50) {
    throw new Error('could not read the CSPm token tables or the library');
  }
  return { keywords, punct, library };
}

/// The repository entries of the embedded CSPm (names prefixed `cspm-`)
/// and the patterns of the block's body. `sc` adds the language suffix.
export function cspmRules(root, sc) {
  const { keywords, punct, library } = readTables(root);
  const problems = [];
  const scopeOf = new Map();
  for (const [scope, words] of Object.entries(KEYWORD_SCOPES)) for (const w of words) scopeOf.set(w, scope);
  for (const k of keywords) if (!scopeOf.has(k.text)) problems.push(`CSPm keyword \`${k.text}\` has no scope in cspm.mjs`);
  for (const w of scopeOf.keys()) if (!keywords.some((k) => k.text === w)) problems.push(`cspm.mjs scopes \`${w}\`, no CSPm keyword`);
  for (const k of Object.keys(PUNCT_SCOPES)) if (!punct.some((p) => p.kind === k)) problems.push(`cspm.mjs scopes ${k}, no CSPm punctuation`);
  if (problems.length) {
    for (const p of problems) console.error(`generate.mjs: ${p}`);
    process.exit(1);
  }
  const repo = {};
  repo['cspm-comments'] = {
    patterns: [
      { name: sc('comment.line.double-dash'), match: `--(?:${NOT_END}.)*` },
      {
        name: sc('comment.block'),
        begin: '\\{-',
        end: '-\\}|(?=csp-end)',
        beginCaptures: { 0: { name: sc('punctuation.definition.comment.begin') } },
        endCaptures: { 0: { name: sc('punctuation.definition.comment.end') } },
      },
    ],
  };
  repo['cspm-strings'] = {
    name: sc('string.quoted.double'),
    match: `"(?:${NOT_END}(?:[^"\\\\\\n]|\\\\.))*"?`,
  };
  const byScope = new Map();
  for (const k of keywords) {
    const s = scopeOf.get(k.text);
    byScope.set(s, [...(byScope.get(s) ?? []), k.text]);
  }
  repo['cspm-keywords'] = {
    patterns: [...byScope].map(([scope, words]) => ({
      name: sc(scope),
      match: `${START}(?:${longestFirst(words).map(escapeRe).join('|')})${END}`,
    })),
  };
  const libByScope = new Map();
  for (const l of library) {
    const s = LIBRARY_SCOPES[l.kind];
    libByScope.set(s, [...(libByScope.get(s) ?? []), l.name]);
  }
  repo['cspm-library'] = {
    comment: "FDR's built-ins and RoboTool's library (crates/hir/src/csp_library.rs).",
    patterns: [...libByScope].map(([scope, names]) => ({
      name: sc(scope),
      match: `${START}(?:${longestFirst(names).map(escapeRe).join('|')})${END}(?!::)`,
    })),
  };
  repo['cspm-definition'] = {
    comment: 'A name defined at the start of a line (or of the block): `P = …`, `f(x) = …`.',
    match: `(?:^|(?<=csp-begin))[ \\t]*(${IDENT})(?=[ \\t]*(?:\\([^=]*\\)[ \\t]*)*=(?!=))`,
    captures: { 1: { name: sc('entity.name.function') } },
  };
  repo['cspm-qualified'] = {
    comment: "A module or model path: `M::` of RoboTool's names (`M::e.in`).",
    match: `(${IDENT})(::)`,
    captures: { 1: { name: sc('entity.name.namespace') }, 2: { name: sc(PUNCT_SCOPES.COLON2) } },
  };
  repo['cspm-identifier'] = { match: IDENT };
  repo['cspm-numbers'] = { name: sc('constant.numeric.integer'), match: `${START}[0-9]+` };
  repo['cspm-operators'] = {
    patterns: longestFirst(punct.map((p) => p.text)).map((text) => {
      const p = punct.find((q) => q.text === text);
      return { name: sc(PUNCT_SCOPES[p.kind] ?? DEFAULT_PUNCT), match: escapeRe(text) };
    }),
  };
  const body = [
    'cspm-comments',
    'cspm-strings',
    'cspm-keywords',
    'cspm-definition',
    'cspm-qualified',
    'cspm-library',
    'cspm-identifier',
    'cspm-numbers',
    'cspm-operators',
  ].map((k) => ({ include: `#${k}` }));
  return { repo, body };
}
