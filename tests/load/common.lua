-- Shared by the surfdeform wrk scripts in this folder (each one loads it
-- from its own folder). It counts status codes, 503s without Retry-After,
-- and the latency of served (2xx) requests alone, which wrk's own latency
-- mixes with the rejections; done() prints one JSON line that
-- scripts/loadtest.sh reads:
--   {"wrk": {"requests":…, "duration_s":…, "codes":{"200":…}, "served":…,
--     "served_ms":{"p50":…,"p90":…,"p99":…,"max":…}, "retry_after_missing":…,
--     "socket_errors":{…}, "latency_ms":{"p50":…,"p99":…}, "bytes":…}}
-- (bytes: every response's, headers included).
-- Served latencies are timed per connection: run wrk with as many threads
-- as connections (-t N -c N), as loadtest.sh does.
local ffi = require("ffi")
ffi.cdef [[
typedef struct { long tv_sec; long tv_nsec; } surfdeform_timespec;
int clock_gettime(int clock_id, surfdeform_timespec *ts);
]]
local clock = ffi.new("surfdeform_timespec")
local CLOCK_MONOTONIC = 1
local function now_us()
  ffi.C.clock_gettime(CLOCK_MONOTONIC, clock)
  return tonumber(clock.tv_sec) * 1e6 + tonumber(clock.tv_nsec) / 1e3
end

local M = {}

function M.read_file(path)
  local f = assert(io.open(path, "rb"), "cannot read " .. tostring(path))
  local bytes = f:read("*a")
  f:close()
  return bytes
end

-- Per thread (wrk runs each thread's script in its own Lua state).
codes = {}
served_us = {}
retry_after_missing = 0
local sent_at = nil

local threads = {}

-- The test build's fault to arm on every request (LOADTEST_FAULT, sent as
-- X-Surfdeform-Fault; surfdeform-server-faults only), or nil.
local fault = os.getenv("LOADTEST_FAULT")
if fault == "" then fault = nil end

-- make_request(): the next request, as wrk.format(...) builds it.
function M.install(make_request)
  function setup(thread)
    table.insert(threads, thread)
  end

  function request()
    sent_at = now_us()
    if fault == nil then return make_request() end
    -- The header goes right after the request line.
    return (make_request():gsub("\r\n", "\r\nX-Surfdeform-Fault: " .. fault .. "\r\n", 1))
  end

  function response(status, headers, body)
    codes[status] = (codes[status] or 0) + 1
    if status >= 200 and status < 300 and sent_at ~= nil then
      served_us[#served_us + 1] = now_us() - sent_at
    end
    if status == 503 and headers["Retry-After"] == nil and headers["retry-after"] == nil then
      retry_after_missing = retry_after_missing + 1
    end
    sent_at = nil
  end

  function done(summary, latency, requests)
    local all_codes, served, missing = {}, {}, 0
    for _, t in ipairs(threads) do
      for status, n in pairs(t:get("codes")) do
        all_codes[status] = (all_codes[status] or 0) + n
      end
      for _, us in ipairs(t:get("served_us")) do served[#served + 1] = us end
      missing = missing + t:get("retry_after_missing")
    end
    table.sort(served)
    local function pct(p)
      if #served == 0 then return 0 end
      return served[math.max(1, math.ceil(#served * p / 100))] / 1000
    end
    local code_parts = {}
    for status, n in pairs(all_codes) do
      code_parts[#code_parts + 1] = string.format('"%d":%d', status, n)
    end
    local e = summary.errors
    io.write(string.format(
      '{"wrk":{"requests":%d,"duration_s":%.3f,"codes":{%s},"served":%d,' ..
      '"served_ms":{"p50":%.3f,"p90":%.3f,"p99":%.3f,"max":%.3f},"retry_after_missing":%d,' ..
      '"socket_errors":{"connect":%d,"read":%d,"write":%d,"timeout":%d},' ..
      '"latency_ms":{"p50":%.3f,"p99":%.3f},"bytes":%d}}\n',
      summary.requests, summary.duration / 1e6, table.concat(code_parts, ","), #served,
      pct(50), pct(90), pct(99), pct(100), missing, e.connect, e.read, e.write, e.timeout,
      latency:percentile(50) / 1000, latency:percentile(99) / 1000, summary.bytes))
  end
end

return M
