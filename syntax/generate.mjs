#!/usr/bin/env node
// Generates the four TextMate grammars of this folder (and the exhaustive
// keyword fixtures under tests/generated/) from one description.
//
// The spellings are not written here: the keywords, the languages each one is
// reserved in, and the punctuation tokens are read from the Rust lexer's table,
// crates/syntax/src/kinds.rs. This file only decides how each token is
// highlighted. It fails when kinds.rs has a keyword or punctuation token that
// has no scope here (or the other way round), so the grammars cannot silently
// fall behind the lexer.
//
//   node generate.mjs           write the grammars and generated fixtures
//   node generate.mjs --check   fail (exit 1) if any written file is stale

import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { cspmRules } from './cspm.mjs';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const KINDS_RS = path.join(HERE, '..', 'crates', 'syntax', 'src', 'kinds.rs');

// ---------------------------------------------------------------------------
// The four languages.

const LANGS = {
  rct: {
    file: 'robochart.tmLanguage.json',
    name: 'RoboChart',
    scopeName: 'source.robochart',
    fileTypes: ['rct'],
    dollar: false,
    assertion: false,
  },
  rst: {
    file: 'robosim.tmLanguage.json',
    name: 'RoboSim',
    scopeName: 'source.robosim',
    fileTypes: ['rst'],
    dollar: true,
    assertion: false,
  },
  assertions: {
    file: 'robochart-assertions.tmLanguage.json',
    name: 'RoboChart Assertions',
    scopeName: 'source.robochart.assertions',
    fileTypes: ['assertions'],
    dollar: false,
    assertion: true,
  },
  rsa: {
    file: 'robosim-assertions.tmLanguage.json',
    name: 'RoboSim Assertions',
    scopeName: 'source.robosim.assertions',
    fileTypes: ['rsa'],
    dollar: true,
    assertion: true,
  },
};

// The `Langs` constants of kinds.rs, as sets of the languages above.
const LANG_SETS = {
  ALL: ['rct', 'rst', 'assertions', 'rsa'],
  RC: ['rct', 'assertions'],
  RS: ['rst', 'rsa'],
  ASSERT: ['assertions', 'rsa'],
  RC_ASSERT: ['assertions'],
  RS_ASSERT: ['rsa'],
};

// ---------------------------------------------------------------------------
// How keywords are highlighted: scope (without the language suffix) -> words.
// Every keyword of kinds.rs must appear exactly once.

const KEYWORD_SCOPES = {
  'constant.language.boolean': ['true', 'false'],
  'variable.language': ['result', 'cycle'],
  // Keywords that introduce a declaration.
  'storage.type': [
    'stm', 'state', 'interface', 'controller', 'module', 'event', 'var', 'const', 'clock',
    'record', 'datatype', 'enumeration', 'type', 'function', 'operation', 'robotic', 'platform',
    'initial', 'junction', 'final', 'probabilistic', 'transition', 'connection',
    'rref', 'cref', 'sref', 'opref', 'diagram',
    'input', 'output', 'context',
    'assertion', 'csp', 'simulation',
  ],
  'storage.modifier': ['_async', '_broadcast', 'mult', 'timed', 'untimed', 'DEFAULT'],
  'keyword.control.import': ['import'],
  'keyword.other.package': ['package'],
  'keyword.control.conditional': ['if', 'then', 'else', 'end'],
  'keyword.control.statement': ['skip', 'wait', 'send', 'exec'],
  'keyword.operator.word': ['not', 'iff', 'cat', 'in', 'is', 'as'],
  'keyword.other.binder': ['forall', 'exists', 'exists1', 'lambda', 'let', 'the'],
  'support.function.builtin': ['since', 'sinceEntry', 'inverse', 'transpose'],
  'support.type.builtin': ['vector', 'matrix'],
  // Clauses and members.
  'keyword.other': [
    'from', 'to', 'on', 'trigger', 'probability', 'condition', 'action',
    'entry', 'during', 'exit', 'uses', 'provides', 'requires',
    'precondition', 'postcondition', 'terminates', 'cycleDef',
  ],
  // Words of the assertion languages.
  'keyword.other.assertion': [
    'and', 'assigned', 'associated', 'constant', 'does', 'equal', 'equals', 'initialised',
    'instantiate', 'of', 'parameter', 'reachable', 'refine', 'refines', 'set', 'terminate',
    'value', 'with',
  ],
  'keyword.other.property': [
    'deadlock-free', 'divergence-free', 'deterministic', 'timelock-free', 'schedulable',
  ],
  'keyword.other.semantic-model': [
    'failures divergences model', 'failures model', 'traces model', 'tick-tock model',
  ],
};

// Keywords followed by the name they declare: [keyword(s), name scope, languages].
// A group of several words (`robotic platform`) must be written in that order.
const MODEL = ['rct', 'rst'];
const DECLARATIONS = [
  [['stm'], 'entity.name.type', MODEL],
  [['interface'], 'entity.name.type', MODEL],
  [['controller'], 'entity.name.type', MODEL],
  [['module'], 'entity.name.type', MODEL],
  [['record'], 'entity.name.type', MODEL],
  [['datatype'], 'entity.name.type', MODEL],
  [['enumeration'], 'entity.name.type', MODEL],
  [['type'], 'entity.name.type', MODEL],
  [['robotic', 'platform'], 'entity.name.type', MODEL],
  [['operation'], 'entity.name.function', MODEL],
  [['function'], 'entity.name.function', MODEL],
  [['state'], 'variable.other.state', MODEL],
  [['initial'], 'variable.other.node', MODEL],
  [['junction'], 'variable.other.node', MODEL],
  [['final'], 'variable.other.node', MODEL],
  [['probabilistic'], 'variable.other.node', MODEL],
  [['transition'], 'variable.other.transition', MODEL],
  [['event'], 'variable.other.event', ['rct', 'rst', 'rsa']],
  [['clock'], 'variable.other.clock', MODEL],
  [['rref'], 'variable.other.instance', MODEL],
  [['cref'], 'variable.other.instance', MODEL],
  [['sref'], 'variable.other.instance', MODEL],
  [['opref'], 'variable.other.instance', MODEL],
  [['diagram'], 'entity.name.section', MODEL],
  [['simulation'], 'entity.name.type', ['rsa']],
  [['csp'], 'entity.name.function', ['assertions', 'rsa']],
  [['assertion'], 'entity.name.label', ['assertions', 'rsa']],
];

// How punctuation is highlighted: kinds.rs token name -> scope. `$`, `Set(`
// and `Seq(` have rules of their own (see below).
const PUNCT_SCOPES = {
  L_CURLY: 'punctuation.section.braces.begin',
  R_CURLY: 'punctuation.section.braces.end',
  L_PAREN: 'punctuation.section.parens.begin',
  R_PAREN: 'punctuation.section.parens.end',
  L_BRACK: 'punctuation.section.brackets.begin',
  R_BRACK: 'punctuation.section.brackets.end',
  L_PAREN_PIPE: 'punctuation.section.tuple.begin',
  R_PAREN_PIPE: 'punctuation.section.tuple.end',
  L_BRACK_PIPE: 'punctuation.section.vector.begin',
  R_BRACK_PIPE: 'punctuation.section.vector.end',
  DEADLINE_OPEN: 'keyword.operator.deadline',
  COLON2_STAR: 'punctuation.separator.namespace.wildcard',
  COLON2: 'punctuation.separator.namespace',
  COLON: 'punctuation.separator.colon',
  COMMA: 'punctuation.separator.comma',
  SEMI: 'punctuation.separator.semicolon',
  AT: 'punctuation.separator.at',
  PIPE: 'punctuation.separator.pipe',
  HASH: 'keyword.operator.clock-reset',
  QUESTION: 'keyword.operator.input',
  BANG: 'keyword.operator.output',
  DOT: 'punctuation.accessor.dot',
  EQ: 'keyword.operator.assignment',
  EQ2: 'keyword.operator.comparison',
  NEQ: 'keyword.operator.comparison',
  LT: 'keyword.operator.comparison',
  LTEQ: 'keyword.operator.comparison',
  GT: 'keyword.operator.comparison',
  GTEQ: 'keyword.operator.comparison',
  PLUS: 'keyword.operator.arithmetic',
  MINUS: 'keyword.operator.arithmetic',
  STAR: 'keyword.operator.arithmetic',
  SLASH: 'keyword.operator.arithmetic',
  PERCENT: 'keyword.operator.arithmetic',
  CARET: 'keyword.operator.concatenation',
  AND: 'keyword.operator.logical',
  OR: 'keyword.operator.logical',
  IMPLIES: 'keyword.operator.logical',
  ARROW: 'keyword.operator.arrow',
  REL_ARROW: 'keyword.operator.arrow.relation',
};
const SPECIAL_PUNCT = ['SET_OPEN', 'SEQ_OPEN', 'DOLLAR'];

// ---------------------------------------------------------------------------
// Reading kinds.rs.

function readKinds() {
  const src = fs.readFileSync(KINDS_RS, 'utf8');
  const block = (name) => {
    const m = new RegExp(`^\\s*${name}\\s*\\{\\n([\\s\\S]*?)^\\s*\\}`, 'm').exec(src);
    if (!m) throw new Error(`kinds.rs: no \`${name} { … }\` block found`);
    return m[1];
  };
  const unescape = (s) => s.replace(/\\(.)/g, '$1');
  const keywords = [];
  for (const m of block('keywords').matchAll(/^\s*([A-Z0-9_]+)\s*=\s*"((?:[^"\\]|\\.)*)"\s+in\s+([A-Z_]+)\s*,/gm)) {
    const langs = LANG_SETS[m[3]];
    if (!langs) throw new Error(`kinds.rs: unknown language set \`${m[3]}\` for ${m[1]}`);
    keywords.push({ kind: m[1], text: unescape(m[2]), langs });
  }
  const punct = [];
  for (const m of block('punct').matchAll(/^\s*([A-Z0-9_]+)\s*=\s*"((?:[^"\\]|\\.)*)"\s*,/gm)) {
    punct.push({ kind: m[1], text: unescape(m[2]) });
  }
  if (keywords.length < 50 || punct.length < 20) throw new Error('kinds.rs: could not read the token tables');
  return { keywords, punct };
}

// Checks that every token of kinds.rs has exactly one scope here and back.
function checkCoverage({ keywords, punct }) {
  const problems = [];
  const scopeOf = new Map();
  for (const [scope, words] of Object.entries(KEYWORD_SCOPES)) {
    for (const w of words) {
      if (scopeOf.has(w)) problems.push(`keyword \`${w}\` has two scopes in generate.mjs`);
      scopeOf.set(w, scope);
    }
  }
  const known = new Set(keywords.map((k) => k.text));
  for (const k of keywords) {
    if (!scopeOf.has(k.text)) problems.push(`keyword \`${k.text}\` (${k.kind}) of kinds.rs has no scope in generate.mjs`);
  }
  for (const w of scopeOf.keys()) {
    if (!known.has(w)) problems.push(`generate.mjs gives a scope to \`${w}\`, which is no keyword in kinds.rs`);
  }
  for (const [words] of DECLARATIONS) {
    for (const w of words) if (!known.has(w)) problems.push(`declaration keyword \`${w}\` is no keyword in kinds.rs`);
  }
  const kinds = new Set(punct.map((p) => p.kind));
  for (const p of punct) {
    if (!PUNCT_SCOPES[p.kind] && !SPECIAL_PUNCT.includes(p.kind)) {
      problems.push(`punctuation ${p.kind} \`${p.text}\` of kinds.rs has no scope in generate.mjs`);
    }
  }
  for (const k of [...Object.keys(PUNCT_SCOPES), ...SPECIAL_PUNCT]) {
    if (!kinds.has(k)) problems.push(`generate.mjs gives a scope to ${k}, which is no punctuation kind in kinds.rs`);
  }
  if (problems.length) {
    for (const p of problems) console.error(`generate.mjs: ${p}`);
    process.exit(1);
  }
  return scopeOf;
}

// ---------------------------------------------------------------------------
// Regular expressions (Oniguruma syntax, as used by vscode-textmate).

const escapeRe = (s) => s.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
// Identifier characters are ASCII only, as in the lexer (`\w` and `\b` would
// also accept non-ASCII letters, which the lexer reports as stray characters).
const IDENT_CONT = '[A-Za-z0-9_]';
const IDENT = '[A-Za-z_][A-Za-z0-9_]*';
// A word token starts here: not inside an identifier and not after the `^`
// escape (`^state` and the `^t` of `s^t` are identifiers). Digits are left out
// on purpose: the lexer ends a number before a letter (`1then` is `1` `then`),
// and a digit inside an identifier is never reached because the identifier
// rule consumes the whole word first. In assertion files a word may also
// follow the `csp-end` that closes a CSP block directly (`csp-endas`).
const startRe = (assertion) => (assertion ? '(?:(?<=csp-end)|(?<![A-Za-z_^]))' : '(?<![A-Za-z_^])');
const END = `(?!${IDENT_CONT})`;

// One keyword as a regex: words of multi-word tokens are separated by spaces
// or tabs (the lexer accepts `[ \t]+` and warns unless it is one space).
const keywordRe = (text) => text.split(' ').map(escapeRe).join('[ \\t]+');

function alternation(texts) {
  // Longest first, so `exists1` is tried before `exists`.
  return [...texts].sort((a, b) => b.length - a.length || a.localeCompare(b)).map(keywordRe).join('|');
}

// ---------------------------------------------------------------------------
// Building one grammar.

function buildGrammar(langKey, tables, scopeOf) {
  const lang = LANGS[langKey];
  const sfx = lang.scopeName.replace(/^source\./, '');
  const sc = (s) => `${s}.${sfx}`;
  const START = startRe(lang.assertion);
  const words = tables.keywords.filter((k) => k.langs.includes(langKey)).map((k) => k.text);
  // A name is any identifier but a reserved word of this language (or the
  // glued tokens `Set(` and `Seq(`); `^` escapes make reserved words names.
  const reserved = `(?!(?:${alternation(words)})${END}|(?:Set|Seq)\\()`;
  const NAME = `${reserved}\\^?${IDENT}`;
  const repo = {};

  repo['namespace-separator'] = {
    comment: 'A `::` inside a name that a rule matches as a whole (package names, `$` references).',
    name: sc(PUNCT_SCOPES.COLON2),
    match: '::',
  };
  repo.comments = {
    patterns: [
      {
        name: sc('comment.line.double-slash'),
        match: '(//).*',
        captures: { 1: { name: sc('punctuation.definition.comment') } },
      },
      {
        name: sc('comment.block'),
        begin: '/\\*',
        end: '\\*/',
        beginCaptures: { 0: { name: sc('punctuation.definition.comment.begin') } },
        endCaptures: { 0: { name: sc('punctuation.definition.comment.end') } },
      },
    ],
  };

  if (lang.assertion) {
    const cspm = cspmRules(path.join(HERE, '..'), (s) => `${s}.cspm`);
    repo['csp-block'] = {
      comment: 'One token: from `csp-begin` to the first `csp-end`, wherever it is (even inside a CSP comment); its text is CSPm (cspm.mjs).',
      name: 'meta.embedded.block.csp',
      begin: `${START}csp-begin${END}`,
      end: 'csp-end',
      beginCaptures: { 0: { name: sc('keyword.other.csp-begin') } },
      endCaptures: { 0: { name: sc('keyword.other.csp-end') } },
      patterns: cspm.body,
    };
    Object.assign(repo, cspm.repo);
  }

  const escapes = {
    patterns: [
      { name: sc('constant.character.escape'), match: '\\\\(?:[btnfr"\'\\\\]|u[0-9A-Fa-f]{4})' },
      { name: sc('invalid.illegal.escape'), match: '\\\\(?:.|$)' },
    ],
  };
  repo['string-escapes'] = escapes;
  repo.strings = {
    patterns: [
      ['"', 'double'],
      ["'", 'single'],
    ].map(([q, kind]) => ({
      name: sc(`string.quoted.${kind}`),
      begin: q,
      end: q,
      beginCaptures: { 0: { name: sc('punctuation.definition.string.begin') } },
      endCaptures: { 0: { name: sc('punctuation.definition.string.end') } },
      patterns: [{ include: '#string-escapes' }],
    })),
  };

  if (lang.dollar) {
    repo.dollar = {
      comment:
        'RoboSim `$` reference: `$`, then (after optional whitespace or comments, possibly on a later line) a qualified name. Ends before anything else, e.g. before a keyword.',
      name: sc('variable.other.dollar'),
      begin: '\\$',
      beginCaptures: { 0: { name: sc('punctuation.definition.variable') } },
      end: `(${NAME}(?:::${NAME})*)|(?=[^ \\t\\r\\n/]|/[^/*])`,
      endCaptures: { 1: { patterns: [{ include: '#namespace-separator' }] } },
      patterns: [{ include: '#comments' }],
    };
  }

  repo.declarations = {
    patterns: DECLARATIONS.filter(([, , langs]) => langs.includes(langKey)).map(([kws, nameScope]) => {
      const captures = {};
      kws.forEach((w, i) => (captures[i + 1] = { name: sc(scopeOf.get(w)) }));
      captures[kws.length + 1] = { name: sc(nameScope) };
      return {
        match: `${START}${kws.map((w) => `(${escapeRe(w)})`).join('[ \\t]+')}[ \\t]+(${NAME})${END}`,
        captures,
      };
    }),
  };
  if (words.includes('package')) {
    repo.declarations.patterns.push({
      match: `${START}(package)[ \\t]+(${NAME}(?:[ \\t]*::[ \\t]*${NAME})*)${END}`,
      captures: {
        1: { name: sc(scopeOf.get('package')) },
        2: { name: sc('entity.name.namespace'), patterns: [{ include: '#namespace-separator' }] },
      },
    });
  }

  // Keywords, grouped by scope; multi-word and hyphenated ones first.
  const keywordPatterns = [];
  const byScope = (pred) => {
    const out = [];
    for (const [scope, ws] of Object.entries(KEYWORD_SCOPES)) {
      const here = ws.filter((w) => words.includes(w) && pred(w));
      if (here.length) out.push({ name: sc(scope), match: `${START}(?:${alternation(here)})${END}` });
    }
    return out;
  };
  keywordPatterns.push(...byScope((w) => /[ -]/.test(w)));
  keywordPatterns.push({
    comment: '`Set(` and `Seq(` are single tokens: `Set (int)` is the identifier `Set`.',
    match: `${START}(Set|Seq)(\\()`,
    captures: { 1: { name: sc('support.type.builtin') }, 2: { name: sc('punctuation.section.parens.begin') } },
  });
  keywordPatterns.push(...byScope((w) => !/[ -]/.test(w)));
  repo.keywords = { patterns: keywordPatterns };

  repo['variable-declarations'] = {
    comment: 'A name followed by `:` declares it: fields, parameters, variables, binders.',
    match: `${START}(${NAME})(?=[ \\t]*:(?!:))`,
    captures: { 1: { name: sc('variable.other.declaration') } },
  };
  repo.calls = {
    comment: 'A name directly followed by `(` (but not `(|`, a record literal, nor a connection suffix `(_async)`).',
    name: sc('meta.function-call'),
    match: `${START}(${NAME})(?=\\((?!\\||[ \\t]*_async${END}))`,
    captures: { 1: { name: sc('entity.name.function') } },
  };
  repo['escaped-identifier'] = {
    comment: '`^name` is an identifier, also when `name` is a keyword (`^exec`), and in `s^t`.',
    name: sc('meta.identifier.escaped'),
    match: `(\\^)${IDENT}`,
    captures: { 1: { name: sc('punctuation.definition.escape') } },
  };
  repo.identifier = { comment: 'Consumes whole identifiers, so nothing matches inside one.', match: IDENT };
  repo.numbers = {
    patterns: [
      // No look-behind needed: a digit inside an identifier is never reached.
      { name: sc('constant.numeric.float'), match: '[0-9]+\\.[0-9]+' },
      { name: sc('constant.numeric.integer'), match: '[0-9]+' },
    ],
  };

  // Punctuation: one rule per token, longest first (`::*` before `::` before `:`).
  const punct = tables.punct.filter((p) => PUNCT_SCOPES[p.kind]);
  punct.sort((a, b) => b.text.length - a.text.length);
  repo.operators = {
    patterns: punct.map((p) => ({ name: sc(PUNCT_SCOPES[p.kind]), match: escapeRe(p.text) })),
  };

  const stray = ['[&`~]', '\\\\(?!/)', '[^\\x00-\\x7F]', '[\\x00-\\x08\\x0B\\x0C\\x0E-\\x1F\\x7F]'];
  if (!lang.dollar) stray.push('\\$');
  repo.invalid = {
    comment: lang.dollar
      ? 'Characters the lexer reports as stray.'
      : 'Characters the lexer reports as stray, and `$`, which only RoboSim files use.',
    name: sc('invalid.illegal.character'),
    match: stray.join('|'),
  };

  const order = [
    'comments',
    ...(lang.assertion ? ['csp-block'] : []),
    'strings',
    ...(lang.dollar ? ['dollar'] : []),
    'declarations',
    'keywords',
    'variable-declarations',
    'calls',
    'escaped-identifier',
    'identifier',
    'numbers',
    'operators',
    'invalid',
  ];
  return {
    information_for_contributors: [
      'This file is generated by syntax/generate.mjs from crates/syntax/src/kinds.rs. Do not edit it:',
      'change generate.mjs (or kinds.rs) and run `node syntax/generate.mjs`.',
    ],
    name: lang.name,
    scopeName: lang.scopeName,
    fileTypes: lang.fileTypes,
    patterns: order.map((k) => ({ include: `#${k}` })),
    repository: repo,
  };
}

// ---------------------------------------------------------------------------
// Exhaustive keyword fixtures: every keyword of the four tables, one per line,
// with its scope in the languages that reserve it and with no keyword scope in
// the others.

function buildKeywordFixture(langKey, tables, scopeOf) {
  const lang = LANGS[langKey];
  const sfx = lang.scopeName.replace(/^source\./, '');
  const all = [...new Set(tables.keywords.map((k) => k.text))];
  const reservedHere = new Set(tables.keywords.filter((k) => k.langs.includes(langKey)).map((k) => k.text));
  const keywordScopes = Object.keys(KEYWORD_SCOPES).map((s) => `${s}.${sfx}`);
  const lines = [
    `// SYNTAX TEST "${lang.scopeName}" "every keyword of kinds.rs (generated by generate.mjs; do not edit)"`,
  ];
  for (const w of all) {
    lines.push(w);
    const mark = `<${'-'.repeat(w.length)}`;
    if (reservedHere.has(w)) {
      lines.push(`// ${mark} ${scopeOf.get(w)}.${sfx}`);
    } else {
      lines.push(`// ${mark} - ${keywordScopes.join(' ')}`);
    }
  }
  return lines.join('\n') + '\n';
}

// ---------------------------------------------------------------------------

function outputs() {
  const tables = readKinds();
  const scopeOf = checkCoverage(tables);
  const files = new Map();
  for (const key of Object.keys(LANGS)) {
    const g = buildGrammar(key, tables, scopeOf);
    files.set(path.join(HERE, LANGS[key].file), JSON.stringify(g, null, 2) + '\n');
    const ext = LANGS[key].fileTypes[0];
    files.set(path.join(HERE, 'tests', 'generated', `keywords.${ext}`), buildKeywordFixture(key, tables, scopeOf));
  }
  return files;
}

const check = process.argv.includes('--check');
const files = outputs();
let stale = 0;
for (const [file, text] of files) {
  const rel = path.relative(HERE, file);
  const old = fs.existsSync(file) ? fs.readFileSync(file, 'utf8') : null;
  if (old === text) continue;
  if (check) {
    console.error(`generate.mjs: ${rel} is out of date: run \`node syntax/generate.mjs\``);
    stale++;
  } else {
    fs.mkdirSync(path.dirname(file), { recursive: true });
    fs.writeFileSync(file, text);
    console.log(`wrote ${rel}`);
  }
}
if (check) {
  if (stale) process.exit(1);
  console.log(`generate.mjs: ${files.size} generated files are up to date with kinds.rs`);
}
