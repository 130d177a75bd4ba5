-- POST /v1/deform naming both the model (uploaded once, POST /v1/models)
-- and a cached surface by id: the body is the parameters alone
-- (application/json), as the viewer and the CLI send them.
--   wrk -t8 -c8 -d10s -s tests/load/deform_model_id.lua URL -- SURFACE_ID MODEL_ID [SUBDIVISION [COMPRESSION]]
-- SUBDIVISION: off (default), adaptive or uniform. COMPRESSION: draco
-- (default: Draco .drc) or meshopt (GLB with EXT_meshopt_compression).
local common = dofile(debug.getinfo(1, "S").source:match("^@(.*/)") .. "common.lua")
local body, headers

function init(args)
  local id, model, mode, compression = args[1], args[2], args[3] or "off", args[4] or "draco"
  assert(id and model, "usage: -- SURFACE_ID MODEL_ID [SUBDIVISION [COMPRESSION]]")
  local output = compression == "meshopt" and '{"compression":"meshopt"}' or '{"format":"drc"}'
  body = string.format(
    '{"surface_id":"%s","model_id":"%s","placement":{"scale":"fit"},"subdivision":{"mode":"%s"},' ..
    '"output":%s}', id, model, mode, output)
  headers = {
    ["Content-Type"] = "application/json",
    ["X-Surfdeform-Surface-Id"] = id,
    ["X-Surfdeform-Model-Id"] = model,
  }
end

common.install(function()
  return wrk.format("POST", "/v1/deform", headers, body)
end)
