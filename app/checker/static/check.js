// The /check page: keeps the trust bundle, reads a QR code three ways (camera, photo, text) and shows
// the offline decision in the verify page's words and colours. Every word shown comes from the page's
// data block (#check-words, made by the server); this file has none of its own.
import { acceptBundle, decide, unpackBundle, Refused } from "./decide.js";

const BUNDLE_URL = "/.well-known/trikecert-trust";
const BUNDLE_CACHE = "trikecert-bundle";
const PINS = "trikecert.pins";
const FETCH_TIMEOUT_MS = 20000;
const words = JSON.parse(document.getElementById("check-words").textContent);
const $ = (id) => document.getElementById(id);
const state = { held: null };

// ---- dates, in the words' formats (app/web/formatting.py long_date; the display time zone) --------
// The page's language may be one the phone's Intl does not know (Debian's Chromium knows none of ha,
// yo, ig, pcm and answers in American English): Intl only finds the calendar day in the time zone,
// and the month is named with the words' months (CLDR's, as the server's pages name it: "3 Disamba
// 2026"). Words without months (an older page kept by the worker) fall back to British English.

function longDate(date, timeZone) {
  const months = Array.isArray(words.months) && words.months.length === 12 ? words.months : null;
  const options = { timeZone, day: "numeric", month: months ? "numeric" : "long", year: "numeric" };
  const parts = new Intl.DateTimeFormat("en-GB", options).formatToParts(date);
  const part = (type) => parts.find((p) => p.type === type).value;
  const month = months ? months[Number(part("month")) - 1] : part("month");
  return `${Number(part("day"))} ${month} ${part("year")}`; // en-GB writes a numeric month's day "04"
}

function checkedAgainst(madeAt) {
  const { prefix, time_zone: timeZone } = words.checked_against;
  const moment = new Date(madeAt * 1000);
  const time = new Intl.DateTimeFormat("en-GB", { timeZone, hour: "2-digit", minute: "2-digit", hourCycle: "h23" })
    .format(moment);
  return `${prefix}${longDate(moment, timeZone)}, ${time}`;
}

function dayOf(yyyymmdd) {
  const y = Math.floor(yyyymmdd / 10000), m = Math.floor(yyyymmdd / 100) % 100, d = yyyymmdd % 100;
  return longDate(new Date(Date.UTC(y, m - 1, d, 12)), "UTC");
}

// ---- the bundle held: Cache Storage (beside the worker's copies of the page), pins in localStorage ---

async function readHeld() {
  try {
    const cache = await caches.open(BUNDLE_CACHE);
    const response = await cache.match(BUNDLE_URL);
    if (!response) return null;
    const text = await response.text();
    const opened = await unpackBundle(text);
    return { ...opened, text, etag: response.headers.get("ETag") };
  } catch {
    return null; // an empty or broken store: no list held, and the page says what to do
  }
}

function readPins() {
  try {
    const pins = JSON.parse(localStorage.getItem(PINS) || "null");
    return pins && typeof pins === "object" && !Array.isArray(pins) ? pins : null;
  } catch {
    return null;
  }
}

async function keep(opened, etag) {
  const headers = { "Content-Type": "application/jose" };
  if (etag) headers.ETag = etag;
  const cache = await caches.open(BUNDLE_CACHE);
  await cache.put(BUNDLE_URL, new Response(opened.text, { headers }));
  const pins = readPins() || {};
  pins[opened.kid] = opened.x; // the key that signed a list we took is trusted from now on
  localStorage.setItem(PINS, JSON.stringify(pins));
}

async function refresh() {
  const held = state.held;
  let response;
  // A road with a weak signal may hold a request open for minutes: give up and keep the list held.
  const abort = new AbortController();
  const timer = setTimeout(() => abort.abort(), FETCH_TIMEOUT_MS);
  try {
    const headers = held && held.etag ? { "If-None-Match": held.etag } : {};
    response = await fetch(BUNDLE_URL, { headers, cache: "no-store", signal: abort.signal });
  } catch {
    return; // offline: the list held (if any) stays
  } finally {
    clearTimeout(timer);
  }
  if (response.status === 304 || !response.ok) return;
  const text = await response.text();
  try {
    // The keys pinned; with none stored (storage cleared), the key of the list held, else first use.
    const pins = readPins() || (held ? { [held.kid]: held.x } : null);
    const opened = await acceptBundle(text, pins, held);
    opened.text = text;
    opened.etag = response.headers.get("ETag");
    await keep(opened, opened.etag);
    state.held = opened;
    $("list-refused").hidden = true;
  } catch (error) {
    const code = error instanceof Refused ? error.code : "bundle_unreadable";
    const said = words.codes[code] || words.codes.bundle_unreadable;
    $("list-refused-headline").textContent = said.headline;
    $("list-refused-sentence").textContent = said.sentence;
    $("list-refused").hidden = false;
    $("list-refused").dataset.code = code;
  }
}

// "Checked against the list of ..." is said once: by the verdict on screen when it names the list it
// was decided by, else by the page's line. A newer list taken after the verdict takes the line back.
function showList() {
  const line = $("list-status");
  const named = $("result").querySelector('[data-slot="checked"]');
  if (named && !(state.held && named.dataset.seq === String(state.held.body.seq))) named.remove();
  line.hidden = Boolean($("result").querySelector('[data-slot="checked"]'));
  line.textContent = state.held ? checkedAgainst(state.held.body.made_at) : words.codes.no_bundle.sentence;
  line.dataset.held = state.held ? String(state.held.body.seq) : "";
}

// ---- the verdict --------------------------------------------------------------------------------

function show(result) {
  const said = words.codes[result.code];
  const box = $("verdict").content.firstElementChild.cloneNode(true);
  const slot = (name) => box.querySelector(`[data-slot="${name}"]`);
  box.classList.add(`status--${said.tone}`);
  box.dataset.code = result.code;
  slot("headline").textContent =
    result.since && words.dated[result.code] ? words.dated[result.code].replace("{date}", dayOf(result.since)) : said.headline;
  slot("sentence").textContent = said.sentence;
  const claims = result.claims;
  // The occupancy in large type only while the paper stands, as on the verify page: a revoked,
  // superseded or expired paper's stated occupancy must not read as a permission.
  const stands = result.code === "certified" || result.code === "refusal";
  if (claims) {
    slot("registration").textContent = claims.registration;
    const kind = claims.compliant ? "certificate" : "refusal";
    slot("number").textContent = `${words.titles[kind]} ${claims.number}`;
    if (stands) slot("occupancy").textContent = words.occupancy[kind][claims.occupants];
  } else {
    for (const name of ["registration-line", "number"]) slot(name).remove();
  }
  if (!claims || !stands) {
    slot("sentence").classList.add("status__occupancy");
    slot("occupancy").remove();
  }
  if (result.bundle) {
    slot("checked").textContent = checkedAgainst(result.bundle.made_at);
    slot("checked").dataset.seq = String(result.bundle.seq);
  } else slot("checked").remove();
  $("result").replaceChildren(box);
  $("list-status").hidden = Boolean(result.bundle);
  box.scrollIntoView({ block: "nearest" });
}

async function check(text) {
  const result = await decide(text, state.held, Math.floor(Date.now() / 1000));
  show(result);
  return result;
}

// ---- three ways to read the code ----------------------------------------------------------------

const LARGEST = 1600; // pixels on the longest side that jsQR is given at most

// A phone's photo is large and a worn print blurred: it is tried smaller too, where jsQR finds more.
function photoSizes(longest) {
  return [Math.min(longest, LARGEST), 1000, 700, 450].filter((target) => target <= longest);
}

// A camera held still over a worn print sends the same picture frame after frame, and jsQR reads a
// picture at some sizes and not at others (about 1 worn print in 1,700 at neither 640 nor 450 pixels):
// each look tries the frame at the next of these fractions of its longest side (at most LARGEST).
const CAMERA_SIZES = [1, 0.875, 0.7, 0.8125, 0.75];

function decodeImage(source, width, height, sizes) {
  const longest = Math.max(width, height);
  for (const target of sizes) {
    const scale = target / longest;
    const canvas = document.createElement("canvas");
    canvas.width = Math.round(width * scale);
    canvas.height = Math.round(height * scale);
    const context = canvas.getContext("2d", { willReadFrequently: true });
    context.drawImage(source, 0, 0, canvas.width, canvas.height);
    const image = context.getImageData(0, 0, canvas.width, canvas.height);
    const found = self.jsQR && self.jsQR(image.data, image.width, image.height, { inversionAttempts: "attemptBoth" });
    if (found && found.data) return found.data;
  }
  return null;
}

async function detector() {
  if (!("BarcodeDetector" in self)) return null;
  try {
    const formats = await self.BarcodeDetector.getSupportedFormats();
    return formats.includes("qr_code") ? new self.BarcodeDetector({ formats: ["qr_code"] }) : null;
  } catch {
    return null;
  }
}

async function readPicture(source, width, height, sizes) {
  const native = await detector();
  if (native) {
    try {
      const [found] = await native.detect(source);
      if (found && found.rawValue) return found.rawValue;
    } catch {
      // fall through to jsQR
    }
  }
  return decodeImage(source, width, height, sizes);
}

async function onPhoto(event) {
  const file = event.target.files && event.target.files[0];
  $("photo-problem").hidden = true;
  if (!file) return;
  let text = null;
  try {
    const bitmap = await createImageBitmap(file);
    const sizes = photoSizes(Math.max(bitmap.width, bitmap.height));
    text = await readPicture(bitmap, bitmap.width, bitmap.height, sizes);
    bitmap.close();
  } catch {
    text = null;
  }
  event.target.value = "";
  if (text === null) {
    $("photo-problem").hidden = false;
    return;
  }
  await check(text);
}

const camera = { stream: null, timer: null };

function stopCamera() {
  clearTimeout(camera.timer);
  if (camera.stream) for (const track of camera.stream.getTracks()) track.stop();
  camera.stream = null;
  $("camera").hidden = true;
  $("camera-stop").hidden = true;
  $("camera-start").hidden = false;
}

async function startCamera() {
  $("camera-problem").hidden = true;
  try {
    camera.stream = await navigator.mediaDevices.getUserMedia({ video: { facingMode: "environment" }, audio: false });
  } catch {
    $("camera-problem").hidden = false;
    return;
  }
  const video = $("camera");
  video.srcObject = camera.stream;
  video.hidden = false;
  $("camera-start").hidden = true;
  $("camera-stop").hidden = false;
  await video.play().catch(() => {});
  let looks = 0;
  const look = async () => {
    if (!camera.stream) return;
    if (video.videoWidth) {
      const longest = Math.min(Math.max(video.videoWidth, video.videoHeight), LARGEST);
      const size = Math.round(longest * CAMERA_SIZES[looks++ % CAMERA_SIZES.length]);
      const text = await readPicture(video, video.videoWidth, video.videoHeight, [size]);
      if (text !== null) {
        stopCamera();
        await check(text);
        return;
      }
    }
    camera.timer = setTimeout(look, 250);
  };
  look();
}

// ---- start: the worker, the list held, then a fresh one when online -------------------------------

async function start() {
  $("text-form").addEventListener("submit", async (event) => {
    event.preventDefault();
    await check($("scanned").value);
    $("scanned").select();
  });
  $("photo").addEventListener("change", onPhoto);
  $("camera-start").addEventListener("click", startCamera);
  $("camera-stop").addEventListener("click", stopCamera);
  if (!navigator.mediaDevices || !navigator.mediaDevices.getUserMedia) {
    $("camera-start").hidden = true;
    $("camera-problem").hidden = false;
  }
  if ("serviceWorker" in navigator) {
    navigator.serviceWorker.register("/check/sw.js", { scope: "/check/" }).catch(() => {});
  }
  state.held = await readHeld();
  showList();
  await refresh();
  showList();
  document.body.dataset.ready = "true";
  window.addEventListener("online", async () => {
    await refresh();
    showList();
  });
}

start();
