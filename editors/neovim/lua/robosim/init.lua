-- Neovim client of the robosim language server (`robosim lsp`) for RoboChart
-- (.rct), RoboSim (.rst) and their assertion files (.assertions, .rsa).
--
--   require('robosim').setup({
--     cmd = { 'robosim', 'lsp' },  -- the server command; only ever taken from here
--     rules = 'paper',             -- or 'robotool'
--     keymaps = false,             -- true for the keys below, or a table of overrides
--   })
--
-- Neovim 0.11+ registers the server with vim.lsp.config/vim.lsp.enable;
-- older versions (0.7 – 0.10) start it with vim.lsp.start_client and attach
-- buffers with vim.lsp.buf_attach_client. The command is never read from
-- files in the project.

local M = {}

--- The file types (and LSP language ids) the server handles.
M.filetypes = { 'robochart', 'robosim', 'robochart-assertions', 'robosim-assertions' }

M.defaults = {
  cmd = { 'robosim', 'lsp' },
  rules = 'paper',
  -- The workspace root is the nearest folder above the file that holds one
  -- of these (RoboTool projects are Eclipse projects), else the file's folder.
  root_markers = { '.project', '.git' },
  keymaps = false,
  on_attach = nil,
  capabilities = nil,
  name = 'robosim',
}

--- The keys `keymaps = true` sets, buffer-locally, in attached buffers.
--- Pass a table to change some of them, e.g. `keymaps = { rename = '<F2>', format = false }`.
M.default_keymaps = {
  hover = 'K',
  definition = 'gd',
  references = 'gr',
  rename = '<leader>rn',
  format = '<leader>f',
  diagnostics = '<leader>e',
  prev_diagnostic = '[d',
  next_diagnostic = ']d',
}

M.config = nil
local legacy_clients = {} -- root folder → client id (Neovim < 0.11)

local function notify(msg, level)
  vim.notify('robosim: ' .. msg, level or vim.log.levels.ERROR)
end

local function format()
  if vim.lsp.buf.format then
    vim.lsp.buf.format({ async = true })
  else
    vim.lsp.buf.formatting() -- Neovim 0.7
  end
end

local function goto_diagnostic(count)
  if vim.diagnostic.jump then
    vim.diagnostic.jump({ count = count, float = true })
  elseif count < 0 then
    vim.diagnostic.goto_prev()
  else
    vim.diagnostic.goto_next()
  end
end

local ACTIONS = {
  hover = { function() vim.lsp.buf.hover() end, 'hover' },
  definition = { function() vim.lsp.buf.definition() end, 'go to definition' },
  references = { function() vim.lsp.buf.references() end, 'references' },
  rename = { function() vim.lsp.buf.rename() end, 'rename' },
  format = { format, 'format the file' },
  diagnostics = { function() vim.diagnostic.open_float() end, 'diagnostics of the line' },
  prev_diagnostic = { function() goto_diagnostic(-1) end, 'previous diagnostic' },
  next_diagnostic = { function() goto_diagnostic(1) end, 'next diagnostic' },
}

--- Sets the recommended keys in `bufnr` (see M.default_keymaps).
function M.set_keymaps(bufnr, keys)
  if type(keys) ~= 'table' then
    keys = {}
  end
  for action, spec in pairs(ACTIONS) do
    local lhs = keys[action]
    if lhs == nil then
      lhs = M.default_keymaps[action]
    end
    if lhs then
      vim.keymap.set('n', lhs, spec[1], { buffer = bufnr, silent = true, desc = 'robosim: ' .. spec[2] })
    end
  end
end

local function on_attach(cfg, client, bufnr)
  if cfg.keymaps then
    M.set_keymaps(bufnr, cfg.keymaps)
  end
  if cfg.on_attach then
    cfg.on_attach(client, bufnr)
  end
end

local function is_dir(path)
  local st = vim.loop.fs_stat(path)
  return st ~= nil and st.type == 'directory'
end

--- The workspace root of a buffer: the nearest folder above its file with
--- one of `markers`, else the file's folder (the current folder if unnamed).
function M.root_dir(bufnr, markers)
  local name = vim.api.nvim_buf_get_name(bufnr)
  if name == '' then
    return vim.loop.cwd()
  end
  local dir = vim.fn.fnamemodify(name, ':p:h')
  local start = dir
  while true do
    for _, m in ipairs(markers or {}) do
      if vim.loop.fs_stat(dir .. '/' .. m) then
        return dir
      end
    end
    local parent = vim.fn.fnamemodify(dir, ':h')
    if parent == dir then
      break
    end
    dir = parent
  end
  return is_dir(start) and start or vim.loop.cwd()
end

local function settings(cfg)
  return { robosim = { rules = cfg.rules } }
end

-- Neovim 0.11+: vim.lsp.config + vim.lsp.enable (attaches on FileType).
local function setup_config(cfg)
  vim.lsp.config(cfg.name, {
    cmd = cfg.cmd,
    filetypes = M.filetypes,
    root_dir = function(bufnr, on_dir)
      on_dir(M.root_dir(bufnr, cfg.root_markers))
    end,
    settings = settings(cfg),
    init_options = { rules = cfg.rules },
    capabilities = cfg.capabilities,
    on_attach = function(client, bufnr)
      on_attach(cfg, client, bufnr)
    end,
  })
  vim.lsp.enable(cfg.name)
end

local function legacy_client_alive(id)
  local client = id and vim.lsp.get_client_by_id(id)
  return client ~= nil and not client:is_stopped()
end

--- Neovim < 0.11: starts (once per root folder) and attaches the client.
function M.attach(bufnr)
  local cfg = M.config
  if not cfg then
    return nil
  end
  bufnr = (bufnr == nil or bufnr == 0) and vim.api.nvim_get_current_buf() or bufnr
  local root = M.root_dir(bufnr, cfg.root_markers)
  local id = legacy_clients[root]
  if not legacy_client_alive(id) then
    id = vim.lsp.start_client({
      name = cfg.name,
      cmd = cfg.cmd,
      root_dir = root,
      settings = settings(cfg),
      init_options = { rules = cfg.rules },
      capabilities = cfg.capabilities,
      on_attach = function(client, b)
        on_attach(cfg, client, b)
      end,
    })
    if not id then
      notify('could not start the language server `' .. table.concat(cfg.cmd, ' ') .. '`')
      return nil
    end
    legacy_clients[root] = id
  end
  vim.lsp.buf_attach_client(bufnr, id)
  return id
end

local function setup_legacy(cfg)
  local group = vim.api.nvim_create_augroup('robosim_lsp', { clear = true })
  vim.api.nvim_create_autocmd('FileType', {
    group = group,
    pattern = M.filetypes,
    callback = function(args)
      M.attach(args.buf)
    end,
  })
  -- Buffers opened before setup().
  for _, b in ipairs(vim.api.nvim_list_bufs()) do
    if vim.api.nvim_buf_is_loaded(b) and vim.tbl_contains(M.filetypes, vim.bo[b].filetype) then
      M.attach(b)
    end
  end
end

local function check(cfg)
  if type(cfg.cmd) ~= 'table' or #cfg.cmd == 0 then
    error("robosim.setup: `cmd` must be a non-empty list such as { 'robosim', 'lsp' }", 3)
  end
  for _, part in ipairs(cfg.cmd) do
    if type(part) ~= 'string' then
      error('robosim.setup: every element of `cmd` must be a string', 3)
    end
  end
  if cfg.rules ~= 'paper' and cfg.rules ~= 'robotool' then
    error("robosim.setup: `rules` must be 'paper' or 'robotool'", 3)
  end
  if cfg.keymaps ~= false and cfg.keymaps ~= true and type(cfg.keymaps) ~= 'table' then
    error('robosim.setup: `keymaps` must be true, false or a table', 3)
  end
end

--- Configures the server and the file types. Call it once from your config.
function M.setup(opts)
  opts = opts or {}
  local cfg = vim.tbl_extend('force', M.defaults, opts) -- shallow: `cmd` is replaced, not merged
  check(cfg)
  M.config = cfg
  require('robosim.filetype').setup()
  if vim.fn.executable(cfg.cmd[1]) ~= 1 then
    notify('`' .. cfg.cmd[1] .. "` is not an executable: set `cmd` in require('robosim').setup()", vim.log.levels.WARN)
  end
  if vim.fn.has('nvim-0.11') == 1 then
    setup_config(cfg)
  else
    setup_legacy(cfg)
  end
end

return M
