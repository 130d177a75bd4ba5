-- POST /v1/deform, the raw mesh as the body, the surface inline in the
-- parameters (X-Surfdeform-Params): the server hashes it and finds it in its
-- cache after the first request.
--   wrk -t8 -c8 -d10s -s tests/load/deform_inline.lua URL -- SURFACE_JSON MESH [SUBDIVISION]
-- SURFACE_JSON: a one-line file {"surface": {...}, "sampling": {...}}.
local common = dofile(debug.getinfo(1, "S").source:match("^@(.*/)") .. "common.lua")
local body, headers

function init(args)
  local surface, mesh, mode = args[1], args[2], args[3] or "off"
  assert(surface and mesh, "usage: -- SURFACE_JSON MESH [SUBDIVISION]")
  local request = common.read_file(surface):gsub("%s+$", "")
  assert(request:sub(-1) == "}", surface .. " is not a JSON object")
  body = common.read_file(mesh)
  headers = {
    ["Content-Type"] = "application/octet-stream",
    ["X-Surfdeform-Params"] = request:sub(1, -2) ..
        string.format(',"placement":{"scale":"fit"},"subdivision":{"mode":"%s"}}', mode),
  }
end

common.install(function()
  return wrk.format("POST", "/v1/deform", headers, body)
end)
