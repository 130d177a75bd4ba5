-- GET /v1/surfaces/{id} (the sheet and its samples as JSON) or, with "svg",
-- GET /v1/surfaces/{id}/flat.svg.
--   wrk -t8 -c8 -d10s -s tests/load/get_surface.lua URL -- SURFACE_ID [svg]
local common = dofile(debug.getinfo(1, "S").source:match("^@(.*/)") .. "common.lua")
local path

function init(args)
  assert(args[1], "usage: -- SURFACE_ID [svg]")
  path = "/v1/surfaces/" .. args[1] .. (args[2] == "svg" and "/flat.svg" or "")
end

common.install(function()
  return wrk.format("GET", path)
end)
