-- File-type detection for RoboChart and RoboSim.
--
--   .rct          robochart
--   .assertions   robochart-assertions
--   .rsa          robosim-assertions
--   .rst          robosim when the content looks like RoboSim, else rst
--
-- `.rst` is also reStructuredText. A `.rst` file is RoboSim when its first
-- non-blank line outside `//` and `/* */` comments is a RoboChart/RoboSim
-- declaration (`package NAME`, `import A::B`, `stm NAME {`, …) and no line
-- outside comments looks like reStructuredText markup (`.. ` or a section
-- underline). Only the first 5000 lines are read. The VS Code extension
-- applies the same rule (editors/vscode/src/rst-detect.ts).

local M = {}

M.MAX_LINES = 5000

local function match_name(s, i)
  return s:match('^%^?[%a_][%w_]*()', i)
end

local function match_qualified(s, i)
  local j = match_name(s, i)
  if not j then
    return nil
  end
  while true do
    local k = s:match('^::()', j)
    local m = k and match_name(s, k)
    if not m then
      return j
    end
    j = m
  end
end

-- Only spaces up to the end of the line, or one of the characters of
-- `allowed` (then anything).
local function rest_ok(s, i, allowed)
  local j = s:match('^%s*()', i)
  if j > #s then
    return true
  end
  return allowed ~= nil and allowed:find(s:sub(j, j), 1, true) ~= nil
end

-- Spaces, a name, then `rest_ok`.
local function name_then(s, i, allowed)
  local n = s:match('^%s+()', i)
  local e = n and match_name(s, n)
  return e ~= nil and rest_ok(s, e, allowed)
end

local BLOCKS = {
  interface = true,
  datatype = true,
  record = true,
  enumeration = true,
  controller = true,
  stm = true,
  module = true,
}

--- Whether a line (comments removed) is the start of a RoboChart/RoboSim item.
function M.is_declaration(line)
  local start = line:match('^%s*()')
  local kw, after = line:match('^(%a+)()', start)
  if not kw then
    return false
  end
  if kw == 'package' or kw == 'import' then
    local n = line:match('^%s+()', after)
    local e = n and match_qualified(line, n)
    if not e then
      return false
    end
    if kw == 'import' then
      e = line:match('^::%*()', e) or e
    end
    return rest_ok(line, e, nil)
  elseif kw == 'type' or kw == 'diagram' then
    return name_then(line, after, nil)
  elseif BLOCKS[kw] then
    return name_then(line, after, '{')
  elseif kw == 'robotic' then
    local p = line:match('^%s+platform()', after)
    return p ~= nil and name_then(line, p, '{')
  elseif kw == 'operation' or kw == 'function' then
    return name_then(line, after, '({')
  end
  return false
end

local ADORNMENT = { ['='] = true, ['-'] = true, ['~'] = true, ['^'] = true, ['*'] = true, ['#'] = true, ['+'] = true }

--- Whether a line is reStructuredText markup: `.. ` or a section underline.
function M.is_rst_line(line)
  local t = line:gsub('%s+$', '')
  if t == '..' or t:sub(1, 3) == '.. ' then
    return true
  end
  local c = t:sub(1, 1)
  return #t >= 3 and ADORNMENT[c] == true and t == string.rep(c, #t)
end

--- The lines with `//` and `/* */` comments replaced by spaces.
function M.strip_comments(lines)
  local out = {}
  local in_block = false
  for n, line in ipairs(lines) do
    if n > M.MAX_LINES then
      break
    end
    local kept = {}
    local i = 1
    while i <= #line do
      if in_block then
        local e = line:find('*/', i, true)
        if e then
          kept[#kept + 1] = ' '
          i = e + 2
          in_block = false
        else
          i = #line + 1
        end
      elseif line:sub(i, i + 1) == '/*' then
        in_block = true
        i = i + 2
      elseif line:sub(i, i + 1) == '//' then
        i = #line + 1
      else
        kept[#kept + 1] = line:sub(i, i)
        i = i + 1
      end
    end
    out[#out + 1] = table.concat(kept)
  end
  return out
end

--- Whether the lines of a `.rst` file are RoboSim.
function M.looks_like_robosim(lines)
  local copy = {}
  for n, l in ipairs(lines) do
    if n > M.MAX_LINES then
      break
    end
    copy[n] = l:gsub('\r$', '')
  end
  if copy[1] then
    copy[1] = copy[1]:gsub('^\239\187\191', '')
  end
  local code = M.strip_comments(copy)
  local first
  for _, l in ipairs(code) do
    if l:match('%S') then
      first = l
      break
    end
  end
  if not first or not M.is_declaration(first) then
    return false
  end
  for _, l in ipairs(code) do
    if M.is_rst_line(l) then
      return false
    end
  end
  return true
end

local function read_lines(path)
  local f = path and io.open(path, 'r')
  if not f then
    return {}
  end
  local lines = {}
  for l in f:lines() do
    lines[#lines + 1] = l
    if #lines >= M.MAX_LINES then
      break
    end
  end
  f:close()
  return lines
end

--- 'robosim' or 'rst' for a `.rst` buffer (or, without a loaded buffer, file).
function M.detect_rst(bufnr, path)
  local lines
  if bufnr and bufnr ~= 0 and vim.api.nvim_buf_is_loaded(bufnr) then
    lines = vim.api.nvim_buf_get_lines(bufnr, 0, M.MAX_LINES, false)
    if #lines == 1 and lines[1] == '' and path and vim.fn.filereadable(path) == 1 then
      lines = read_lines(path)
    end
  else
    lines = read_lines(path)
  end
  return M.looks_like_robosim(lines) and 'robosim' or 'rst'
end

M.extensions = {
  rct = 'robochart',
  assertions = 'robochart-assertions',
  rsa = 'robosim-assertions',
}

local function lua_filetype_detection()
  if vim.filetype == nil or vim.filetype.add == nil then
    return false
  end
  if vim.fn.has('nvim-0.8') == 1 then
    return vim.g.do_legacy_filetype ~= 1
  end
  return vim.g.do_filetype_lua == 1
end

local did_setup = false

--- Registers the detection; idempotent. Called by ftdetect/robosim.lua and
--- by require('robosim').setup().
function M.setup()
  if did_setup then
    return
  end
  did_setup = true
  if lua_filetype_detection() then
    -- Neovim 0.8+ (filetype.lua).
    local ext = vim.deepcopy(M.extensions)
    ext.rst = function(path, bufnr)
      return M.detect_rst(bufnr, path)
    end
    vim.filetype.add({ extension = ext })
    return
  end
  -- Neovim 0.7 (filetype.vim). ftdetect scripts run after filetype.vim's own
  -- autocommands, so `*.rst` has already been set to rst here and is
  -- overridden only when the content is RoboSim.
  local group = vim.api.nvim_create_augroup('robosim_filetype', { clear = true })
  for e, ft in pairs(M.extensions) do
    vim.api.nvim_create_autocmd({ 'BufNewFile', 'BufRead' }, {
      group = group,
      pattern = '*.' .. e,
      command = 'setfiletype ' .. ft,
    })
  end
  vim.api.nvim_create_autocmd({ 'BufNewFile', 'BufRead' }, {
    group = group,
    pattern = '*.rst',
    callback = function(args)
      if M.detect_rst(args.buf, vim.api.nvim_buf_get_name(args.buf)) == 'robosim' then
        vim.bo[args.buf].filetype = 'robosim'
      end
    end,
  })
end

return M
