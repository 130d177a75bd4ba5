-- POST /v1/deform, the raw mesh as the body, a cached surface by id, the
-- parameters in X-Surfdeform-Params (and the id in X-Surfdeform-Surface-Id,
-- as the CLI and the viewer send it).
--   wrk -t8 -c8 -d10s -s tests/load/deform_by_id.lua URL -- SURFACE_ID MESH [SUBDIVISION]
-- SUBDIVISION: off (default), adaptive or uniform.
local common = dofile(debug.getinfo(1, "S").source:match("^@(.*/)") .. "common.lua")
local body, headers

function init(args)
  local id, mesh, mode = args[1], args[2], args[3] or "off"
  assert(id and mesh, "usage: -- SURFACE_ID MESH [SUBDIVISION]")
  body = common.read_file(mesh)
  headers = {
    ["Content-Type"] = "application/octet-stream",
    ["X-Surfdeform-Surface-Id"] = id,
    ["X-Surfdeform-Params"] = string.format(
      '{"surface_id":"%s","placement":{"scale":"fit"},"subdivision":{"mode":"%s"}}', id, mode),
  }
end

common.install(function()
  return wrk.format("POST", "/v1/deform", headers, body)
end)
