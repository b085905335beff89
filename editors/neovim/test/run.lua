-- Headless test of the plugin against the real server. Run by ../test.sh as
--   nvim --headless -u NONE -i NONE -n -c 'luafile test/run.lua'
-- with ROBOSIM_BIN (the server), ROBOSIM_NVIM_PLUGIN (editors/neovim),
-- ROBOSIM_TESTDATA (editors/testdata) and ROBOSIM_WORKSPACE (an empty
-- temporary folder) in the environment. Prints one line per check and a
-- closing `N passed, M failed, K skipped`, also written to
-- $ROBOSIM_RESULT_FILE if set; exits 0 when every check passed, 1 otherwise.

local bin = assert(os.getenv('ROBOSIM_BIN'), 'ROBOSIM_BIN is not set')
local plugin = assert(os.getenv('ROBOSIM_NVIM_PLUGIN'), 'ROBOSIM_NVIM_PLUGIN is not set')
local testdata = assert(os.getenv('ROBOSIM_TESTDATA'), 'ROBOSIM_TESTDATA is not set')
local workspace = assert(os.getenv('ROBOSIM_WORKSPACE'), 'ROBOSIM_WORKSPACE is not set')
local TIMEOUT = 20000

local passed, failed, skipped = 0, 0, 0

local function out(line)
  io.stdout:write(line .. '\n')
  io.stdout:flush()
end

local function check(name, cond, detail)
  if cond then
    passed = passed + 1
    out('ok - ' .. name)
  else
    failed = failed + 1
    out('not ok - ' .. name .. (detail and (': ' .. detail) or ''))
  end
  return cond
end

local function skip(name, why)
  skipped = skipped + 1
  out('skip - ' .. name .. ': ' .. why)
end

local function inspect(v)
  return (vim.inspect(v):gsub('%s+', ' '))
end

local function finish()
  for _, c in ipairs(vim.lsp.get_clients and vim.lsp.get_clients() or vim.lsp.get_active_clients()) do
    pcall(function()
      c:stop(true)
    end)
  end
  local summary = string.format('%d passed, %d failed, %d skipped', passed, failed, skipped)
  out(summary)
  local result_file = os.getenv('ROBOSIM_RESULT_FILE')
  if result_file then
    local f = assert(io.open(result_file, 'w'))
    f:write(summary .. '\n')
    f:close()
  end
  if failed > 0 then
    vim.cmd('cquit 1')
  else
    vim.cmd('qall!')
  end
end

local function robosim_clients(bufnr)
  local list = {}
  if vim.lsp.get_clients then
    list = vim.lsp.get_clients({ bufnr = bufnr, name = 'robosim' })
  elseif bufnr then
    for _, c in pairs(vim.lsp.buf_get_clients(bufnr)) do
      if c.name == 'robosim' then
        table.insert(list, c)
      end
    end
  else
    for _, c in ipairs(vim.lsp.get_active_clients()) do
      if c.name == 'robosim' then
        table.insert(list, c)
      end
    end
  end
  return list
end

local function code_of(d)
  if d.code ~= nil then
    return d.code
  end
  local lsp = d.user_data and d.user_data.lsp
  return lsp and lsp.code
end

local function edit(path)
  vim.cmd('edit ' .. vim.fn.fnameescape(path))
  return vim.api.nvim_get_current_buf()
end

local function copy(from, to)
  local f = assert(io.open(from, 'rb'))
  local data = f:read('*a')
  f:close()
  local g = assert(io.open(to, 'wb'))
  g:write(data)
  g:close()
end

local function main()
  out('# ' .. vim.split(vim.fn.execute('version'), '\n', { trimempty = true })[1])
  out('# API path: ' .. (vim.fn.has('nvim-0.11') == 1 and 'vim.lsp.config + vim.lsp.enable (0.11+)'
    or 'vim.lsp.start_client + vim.lsp.buf_attach_client (< 0.11)'))

  vim.o.hidden = true -- leave modified buffers when editing another file (0.7)
  vim.opt.runtimepath:prepend(plugin)
  vim.cmd('filetype on') -- sources ftdetect/robosim.lua from the runtimepath

  -- Record every publishDiagnostics (the handler is looked up at dispatch).
  local published = {}
  local default_handler = vim.lsp.handlers['textDocument/publishDiagnostics']
  vim.lsp.handlers['textDocument/publishDiagnostics'] = function(err, result, ctx, config)
    if result then
      published[result.uri] = published[result.uri] or {}
      table.insert(published[result.uri], result)
    end
    return default_handler(err, result, ctx, config)
  end

  -- 1. File types, before any server is set up.
  local expected_ext = { rct = 'robochart', assertions = 'robochart-assertions', rsa = 'robosim-assertions' }
  local files = vim.fn.glob(testdata .. '/filetype/*', false, true)
  table.sort(files)
  check('filetype fixtures exist', #files >= 11, tostring(#files))
  for _, path in ipairs(files) do
    local name = vim.fn.fnamemodify(path, ':t')
    local ext = vim.fn.fnamemodify(path, ':e')
    local want = expected_ext[ext]
    if ext == 'rst' then
      want = name:match('^sim%-') and 'robosim' or 'rst'
    end
    local buf = edit(path)
    check('filetype of ' .. name .. ' is ' .. want, vim.bo[buf].filetype == want, 'got ' .. vim.bo[buf].filetype)
    vim.cmd('bwipeout!')
  end
  local new_rst = workspace .. '/new-document.rst'
  local buf = edit(new_rst)
  check('a new, empty .rst file is rst', vim.bo[buf].filetype == 'rst', 'got ' .. vim.bo[buf].filetype)
  vim.cmd('bwipeout!')

  -- 2. The language server.
  for _, f in ipairs({ 'broken.rct', 'counter.rst' }) do
    copy(testdata .. '/lsp/' .. f, workspace .. '/' .. f)
  end
  copy(testdata .. '/filetype/doc-title.rst', workspace .. '/notes.rst')

  require('robosim').setup({ cmd = { bin, 'lsp' }, rules = 'paper', keymaps = true })

  local broken = edit(workspace .. '/broken.rct')
  check('broken.rct is robochart', vim.bo[broken].filetype == 'robochart')
  local attached = vim.wait(TIMEOUT, function()
    return #robosim_clients(broken) > 0
  end, 20)
  if not check('the server attaches to a .rct buffer', attached) then
    return
  end
  local client = robosim_clients(broken)[1]
  check('the client runs the command from setup()', client.config.cmd[1] == bin, inspect(client.config.cmd))
  -- What the client answers to workspace/configuration (section `robosim`).
  local settings = client.settings or client.config.settings or {}
  check('rules = paper is in the `robosim` settings section',
    settings.robosim ~= nil and settings.robosim.rules == 'paper', inspect(settings))

  local syn
  vim.wait(TIMEOUT, function()
    for _, d in ipairs(vim.diagnostic.get(broken)) do
      if code_of(d) == 'SYN-01' then
        syn = d
        return true
      end
    end
    return false
  end, 20)
  if check('SYN-01 is published for broken.rct', syn ~= nil, inspect(vim.diagnostic.get(broken))) then
    check(
      'SYN-01 is at line 4, columns 22-23 (0-based)',
      syn.lnum == 4 and syn.col == 22 and syn.end_lnum == 4 and syn.end_col == 23,
      inspect({ syn.lnum, syn.col, syn.end_lnum, syn.end_col })
    )
    check('SYN-01 is an error', syn.severity == vim.diagnostic.severity.ERROR)
    check('it is the only diagnostic', #vim.diagnostic.get(broken) == 1, inspect(vim.diagnostic.get(broken)))
  end

  local map = vim.fn.maparg('K', 'n', false, true)
  check('keymaps = true maps K to hover in the buffer', type(map) == 'table' and map.buffer == 1, inspect(map))
  check('…and gd, gr, [d, ]d', vim.fn.maparg('gd', 'n') ~= '' and vim.fn.maparg('gr', 'n') ~= ''
    and vim.fn.maparg('[d', 'n') ~= '' and vim.fn.maparg(']d', 'n') ~= '')

  -- Fix the document: the server gets didChange, the diagnostics clear.
  local line = vim.api.nvim_buf_get_lines(broken, 4, 5, false)[1]
  vim.api.nvim_buf_set_lines(broken, 4, 5, false, { (line:gsub('1;', '1')) })
  local cleared = vim.wait(TIMEOUT, function()
    return #vim.diagnostic.get(broken) == 0
  end, 20)
  check('an edit that fixes the file clears its diagnostics', cleared, inspect(vim.diagnostic.get(broken)))

  -- A well-formed RoboSim file: detected, attached to the same client, clean.
  local counter = edit(workspace .. '/counter.rst')
  local counter_uri = vim.uri_from_bufnr(counter)
  check('counter.rst is robosim', vim.bo[counter].filetype == 'robosim', vim.bo[counter].filetype)
  local got = vim.wait(TIMEOUT, function()
    return published[counter_uri] ~= nil and #robosim_clients(counter) > 0
  end, 20)
  if check('diagnostics are published for counter.rst', got) then
    local last = published[counter_uri][#published[counter_uri]]
    check('…and there are none', #last.diagnostics == 0 and #vim.diagnostic.get(counter) == 0, inspect(last))
  end
  check('one client serves both buffers', #robosim_clients(nil) == 1, tostring(#robosim_clients(nil)))

  local params = { textDocument = { uri = counter_uri } }
  local responses = vim.lsp.buf_request_sync(counter, 'textDocument/documentSymbol', params, TIMEOUT) or {}
  local names = {}
  local function walk(list)
    for _, s in ipairs(list or {}) do
      names[s.name] = true
      walk(s.children)
    end
  end
  for _, r in pairs(responses) do
    walk(r.result)
  end
  check('documentSymbol names Ticks, Counter and Counting', names.Ticks and names.Counter and names.Counting, inspect(names))

  local caps = client.server_capabilities or {}
  check('the server advertises hover and definition', caps.hoverProvider and caps.definitionProvider, inspect(caps))
  local text = vim.api.nvim_buf_get_lines(counter, 10, 11, false)[1]
  local col = text:find('Ticks', 1, true)
  local hover = vim.lsp.buf_request_sync(counter, 'textDocument/hover', {
    textDocument = { uri = counter_uri },
    position = { line = 10, character = col + 1 },
  }, TIMEOUT) or {}
  local contents
  for _, r in pairs(hover) do
    contents = contents or (r.result and r.result.contents)
  end
  check('hover on Ticks mentions it', contents ~= nil and inspect(contents):find('Ticks', 1, true) ~= nil, inspect(contents))

  -- Go to definition through the user-facing command: the cursor jumps to
  -- `interface Ticks` on line 4 (1-based).
  vim.api.nvim_set_current_buf(counter)
  vim.api.nvim_win_set_cursor(0, { 11, col })
  vim.lsp.buf.definition()
  local jumped = vim.wait(TIMEOUT, function()
    return vim.api.nvim_win_get_cursor(0)[1] == 4
  end, 20)
  check('go to definition on Ticks jumps to line 4', jumped, inspect(vim.api.nvim_win_get_cursor(0)))

  -- A reStructuredText .rst stays rst and gets no client.
  local notes = edit(workspace .. '/notes.rst')
  check('notes.rst (reStructuredText) stays rst', vim.bo[notes].filetype == 'rst', vim.bo[notes].filetype)
  vim.wait(200)
  check('…and no robosim client attaches to it', #robosim_clients(notes) == 0)

  -- A csp block of an assertion file: the CSPm engine's diagnostic at its
  -- exact place in the file, and the hover of a library process.
  copy(testdata .. '/lsp/csp.assertions', workspace .. '/csp.assertions')
  local csp = edit(workspace .. '/csp.assertions')
  check('csp.assertions is robochart-assertions', vim.bo[csp].filetype == 'robochart-assertions', vim.bo[csp].filetype)
  local unresolved
  vim.wait(TIMEOUT, function()
    for _, d in ipairs(vim.diagnostic.get(csp)) do
      if code_of(d) == 'CSP-N01' then
        unresolved = d
        return true
      end
    end
    return false
  end, 20)
  if check('CSP-N01 is published for the csp block', unresolved ~= nil, inspect(vim.diagnostic.get(csp))) then
    check(
      'CSP-N01 is on `Undefined`: line 4, columns 34-43 (0-based)',
      unresolved.lnum == 4 and unresolved.col == 34 and unresolved.end_lnum == 4 and unresolved.end_col == 43,
      inspect({ unresolved.lnum, unresolved.col, unresolved.end_lnum, unresolved.end_col })
    )
    check('…and it is the only diagnostic', #vim.diagnostic.get(csp) == 1, inspect(vim.diagnostic.get(csp)))
  end
  local csp_line = vim.api.nvim_buf_get_lines(csp, 4, 5, false)[1]
  local start_by = csp_line:find('StartBy', 1, true)
  local csp_hover = vim.lsp.buf_request_sync(csp, 'textDocument/hover', {
    textDocument = { uri = vim.uri_from_bufnr(csp) },
    position = { line = 4, character = start_by + 1 },
  }, TIMEOUT) or {}
  local csp_contents
  for _, r in pairs(csp_hover) do
    csp_contents = csp_contents or (r.result and r.result.contents)
  end
  check(
    'hover on StartBy explains the library process',
    csp_contents ~= nil and inspect(csp_contents):find('must perform its first event within', 1, true) ~= nil,
    inspect(csp_contents)
  )

  -- Shut down.
  client:stop()
  local stopped = vim.wait(TIMEOUT, function()
    return client:is_stopped()
  end, 20)
  check('the client stops (shutdown, exit)', stopped)
end

local ok, err = xpcall(main, debug.traceback)
if not ok then
  check('the test script runs without error', false, err)
end
finish()
