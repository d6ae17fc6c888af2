-- wrk script: POST realistic inspection bodies (three repeated readings per wheel, an overall
-- weight) for a rotating set of registered vehicles, with the station key from the environment.
-- TRIKECERT_BENCH_IDEMPOTENCY=1 sends a fresh Idempotency-Key with every request.
local key = os.getenv("TRIKECERT_BENCH_KEY")
local vehicles = tonumber(os.getenv("TRIKECERT_BENCH_VEHICLES") or "20")
local idempotent = os.getenv("TRIKECERT_BENCH_IDEMPOTENCY") == "1"
local counter = 0
local threads = 0

wrk.method = "POST"
wrk.headers["Content-Type"] = "application/json"
wrk.headers["Authorization"] = "Bearer " .. key

setup = function(thread)
  threads = threads + 1
  thread:set("thread_id", threads)
end

request = function()
  counter = counter + 1
  local front = 108 + (counter % 5) * 0.1
  local body = string.format(
    '{"registration_number": "BEN %04d", "readings": {"front_kg": [%.1f, %.1f, %.1f], ' ..
    '"left_rear_kg": [115.0, 115.2, 114.8], "right_rear_kg": [135.0, 134.8, 135.2], "overall_kg": 359}}',
    counter % vehicles, front, front, front)
  local headers = nil
  if idempotent then
    headers = {}  -- wrk.format takes these instead of wrk.headers, not besides them
    for name, value in pairs(wrk.headers) do headers[name] = value end
    headers["Idempotency-Key"] = string.format("bench-%d-%d-%d", os.time(), thread_id or 0, counter)
  end
  return wrk.format(nil, "/api/v1/inspections", headers, body)
end

done = function(summary, latency, requests)
  io.write(string.format("non-2xx/3xx: %d\n", summary.errors.status))
end
