-- POST /v1/surfaces with a JSON surface request. With "new", every request
-- asks for a surface not flattened yet (the sampling's nu changes), so each
-- one flattens; otherwise all after the first are cache hits.
--   wrk -t8 -c8 -d10s -s tests/load/surfaces.lua URL -- SURFACE_JSON [new]
local common = dofile(debug.getinfo(1, "S").source:match("^@(.*/)") .. "common.lua")
local request, fresh
local counter = 0
local headers = {["Content-Type"] = "application/json"}

function init(args)
  assert(args[1], "usage: -- SURFACE_JSON [new]")
  request = common.read_file(args[1]):gsub("%s+$", "")
  fresh = args[2] == "new"
  -- Threads start from different values so that they ask for different surfaces.
  counter = math.random(0, 1e9)
end

common.install(function()
  local body = request
  if fresh then
    counter = counter + 1
    -- A new sampling resolution and a new frame origin: a new surface id.
    body = request:sub(1, -2) .. string.format(',"flatten":{"tolerance":%.12g}}', 1e-7 * (1 + (counter % 1e6) / 1e6))
  end
  return wrk.format("POST", "/v1/surfaces", headers, body)
end)
