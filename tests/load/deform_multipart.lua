-- POST /v1/deform as a browser form sends it: multipart/form-data with a
-- "mesh" part (the file) and a "params" part (JSON naming a cached surface).
--   wrk -t8 -c8 -d10s -s tests/load/deform_multipart.lua URL -- SURFACE_ID MESH [SUBDIVISION]
local common = dofile(debug.getinfo(1, "S").source:match("^@(.*/)") .. "common.lua")
local body, headers
local boundary = "surfdeform-load-7d1f0c"

function init(args)
  local id, mesh, mode = args[1], args[2], args[3] or "off"
  assert(id and mesh, "usage: -- SURFACE_ID MESH [SUBDIVISION]")
  local params = string.format(
    '{"surface_id":"%s","placement":{"scale":"fit"},"subdivision":{"mode":"%s"}}', id, mode)
  local name = mesh:match("([^/]+)$")
  body = table.concat({
    "--" .. boundary,
    'Content-Disposition: form-data; name="mesh"; filename="' .. name .. '"',
    "Content-Type: application/octet-stream", "", common.read_file(mesh),
    "--" .. boundary,
    'Content-Disposition: form-data; name="params"',
    "Content-Type: application/json", "", params,
    "--" .. boundary .. "--", ""}, "\r\n")
  headers = {
    ["Content-Type"] = "multipart/form-data; boundary=" .. boundary,
    ["X-Surfdeform-Surface-Id"] = id,
  }
end

common.install(function()
  return wrk.format("POST", "/v1/deform", headers, body)
end)
