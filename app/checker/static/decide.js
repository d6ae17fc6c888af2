// The offline decision of /check (BUNDLE-SPEC.md, "The decision"), pure: no page, no storage.
// It reads the QR text as app/trust/cwt.py does (base45, strict CBOR, COSE_Sign1 with Ed25519) and
// decides it against a trust bundle already accepted by acceptBundle. Codes only: the words come
// from the server (the page's data block), never from here.

const B45 = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ $%*+-./:";
const CLOCK_SLACK = 300; // seconds a device clock may run behind the bundle, and a key's start early
const KID_BYTES = 12;
const EDDSA = -8;
const COSE_SIGN1 = 18;
const CLAIM_ISS = 1, CLAIM_EXP = 4, CLAIM_IAT = 6, CLAIM_OURS = -65537;
const NUMBER = 1, REGISTRATION = 2, COMPLIANT = 3, MAX_OCCUPANTS = 4, KIND = 5;
const CHECK_ALPHABET = "ABCDEFGHJKLMNPRSTUVWXYZ";

/** Why a text or a bundle is not decided further: a stable code (BUNDLE-SPEC.md) and a detail. */
export class Refused extends Error {
  constructor(code, detail) {
    super(detail);
    this.code = code;
  }
}

// ---- base45 (RFC 9285) --------------------------------------------------------------------------

/** The bytes of base45 text; Refused("damaged") when it is not valid base45. */
export function base45Decode(text) {
  const values = [];
  for (const char of text) {
    const value = B45.indexOf(char);
    if (value < 0) throw new Refused("damaged", "not base45 text");
    values.push(value);
  }
  if (values.length % 3 === 1) throw new Refused("damaged", "base45 text of a wrong length");
  const out = [];
  for (let i = 0; i < values.length; i += 3) {
    if (i + 2 < values.length) {
      const n = values[i] + values[i + 1] * 45 + values[i + 2] * 2025;
      if (n > 0xffff) throw new Refused("damaged", "base45 group out of range");
      out.push(n >> 8, n & 0xff);
    } else {
      const n = values[i] + values[i + 1] * 45;
      if (n > 0xff) throw new Refused("damaged", "base45 group out of range");
      out.push(n);
    }
  }
  return new Uint8Array(out);
}

// ---- strict CBOR (RFC 8949): the subset a CWT uses, in its shortest form, nothing after it ------

/** A CBOR tag and its content. */
export class Tagged {
  constructor(tag, value) {
    this.tag = tag;
    this.value = value;
  }
}

/** A CBOR float (never valid in our claims, kept apart from integers). */
class Float {
  constructor(value) {
    this.value = value;
  }
}

const utf8 = new TextDecoder("utf-8", { fatal: true });

/** Decode CBOR that is complete and canonical as cbor2 re-encodes it; throws Refused(code) else. */
export function decodeCbor(bytes, code = "damaged") {
  let at = 0;
  const fail = (why) => {
    throw new Refused(code, why);
  };
  const byte = () => (at < bytes.length ? bytes[at++] : fail("truncated CBOR"));
  const argument = (info) => {
    if (info < 24) return info;
    const sizes = { 24: 1, 25: 2, 26: 4, 27: 8 };
    const size = sizes[info];
    if (size === undefined) fail("indefinite or reserved CBOR length");
    let value = 0n;
    for (let i = 0; i < size; i++) value = (value << 8n) | BigInt(byte());
    const least = { 1: 24n, 2: 0x100n, 4: 0x10000n, 8: 0x100000000n }[size];
    if (value < least) fail("CBOR not in its shortest form");
    return value <= BigInt(Number.MAX_SAFE_INTEGER) ? Number(value) : value;
  };
  const take = (length) => {
    if (typeof length !== "number" || at + length > bytes.length) fail("truncated CBOR");
    const part = bytes.slice(at, at + length);
    at += length;
    return part;
  };
  const item = (depth) => {
    if (depth > 16) fail("CBOR nested too deep");
    const initial = byte();
    const major = initial >> 5, info = initial & 31;
    if (major === 7) {
      if (info === 20) return false;
      if (info === 21) return true;
      if (info === 22) return null;
      if (info === 27) {
        const view = new DataView(take(8).buffer);
        return new Float(view.getFloat64(0));
      }
      return fail("a CBOR simple value or float that is not allowed");
    }
    const n = argument(info);
    switch (major) {
      case 0:
        return n;
      case 1:
        return typeof n === "bigint" || n >= Number.MAX_SAFE_INTEGER ? -1n - BigInt(n) : -1 - n;
      case 2:
        return take(n);
      case 3:
        try {
          return utf8.decode(take(n));
        } catch {
          return fail("CBOR text that is not UTF-8");
        }
      case 4: {
        if (typeof n !== "number") fail("CBOR array too long");
        const list = [];
        for (let i = 0; i < n; i++) list.push(item(depth + 1));
        return list;
      }
      case 5: {
        if (typeof n !== "number") fail("CBOR map too long");
        const map = new Map();
        for (let i = 0; i < n; i++) {
          const key = item(depth + 1);
          if (typeof key !== "number" && typeof key !== "string") fail("a CBOR map key of another type");
          if (map.has(key)) fail("a CBOR map key twice");
          map.set(key, item(depth + 1));
        }
        return map;
      }
      default:
        return new Tagged(n, item(depth + 1));
    }
  };
  const value = item(0);
  if (at !== bytes.length) fail("bytes after the CBOR item");
  return value;
}

function cborHead(major, length) {
  if (length < 24) return [(major << 5) | length];
  if (length < 0x100) return [(major << 5) | 24, length];
  if (length < 0x10000) return [(major << 5) | 25, length >> 8, length & 0xff];
  return [(major << 5) | 26, (length >>> 24) & 0xff, (length >> 16) & 0xff, (length >> 8) & 0xff, length & 0xff];
}

/** The COSE Sig_structure that was signed: ["Signature1", protected, h'', payload] in CBOR. */
function sigStructure(protectedBytes, payload) {
  const label = new TextEncoder().encode("Signature1");
  const parts = [
    [0x84],
    cborHead(3, label.length), label,
    cborHead(2, protectedBytes.length), protectedBytes,
    [0x40],
    cborHead(2, payload.length), payload,
  ];
  const out = [];
  for (const part of parts) for (const b of part) out.push(b);
  return new Uint8Array(out);
}

// ---- Ed25519: WebCrypto first, the vendored @noble/ed25519 where the browser lacks it -----------

let noble = null;
// Which engine verified last: "webcrypto" or "noble" (a test can force "noble").
export const engine = { used: null };

/** True when the Ed25519 signature over message verifies with the 32-byte public key. */
export async function ed25519Verify(publicKey, signature, message) {
  if (publicKey.length !== 32 || signature.length !== 64) return false;
  if (engine.used !== "noble") {
    let key = null;
    try {
      key = await crypto.subtle.importKey("raw", publicKey, { name: "Ed25519" }, false, ["verify"]);
    } catch (error) {
      if (error instanceof DOMException && error.name === "DataError") return false; // not a key
      key = null; // NotSupportedError: this browser has no Ed25519 in WebCrypto
    }
    if (key) {
      engine.used = "webcrypto";
      return crypto.subtle.verify({ name: "Ed25519" }, key, signature, message);
    }
  }
  noble = noble || (await import("./vendor/noble-ed25519.js"));
  engine.used = "noble";
  try {
    return await noble.verifyAsync(signature, message, publicKey, { zip215: false });
  } catch {
    return false;
  }
}

// ---- base64url ----------------------------------------------------------------------------------

/** The bytes of unpadded base64url text, or null when it is not exactly that. */
export function base64url(text) {
  if (typeof text !== "string" || !/^[A-Za-z0-9_-]*$/.test(text) || text.length % 4 === 1) return null;
  const binary = atob(text.replace(/-/g, "+").replace(/_/g, "/") + "=".repeat((4 - (text.length % 4)) % 4));
  const bytes = Uint8Array.from(binary, (c) => c.charCodeAt(0));
  return encode64url(bytes) === text ? bytes : null;
}

function encode64url(bytes) {
  let binary = "";
  for (const b of bytes) binary += String.fromCharCode(b);
  return btoa(binary).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

// ---- the text scanned: a QR URL of ours, a bare payload, an older paper, or something else -------
// As app/trust/offline.py read_text: a /V/ URL (any scheme and host; the payload percent-decoded
// once), or bare text beginning with RRQ (base45 of 0xD2 0x84: tag 18, an array of four) is ours.

const URL_V = /^[A-Za-z][A-Za-z0-9+.-]*:\/\/[^/?#\s]+(?:\/[^?#]*)?\/[Vv]\/([^?#]+)$/;
const LEGACY = /^[A-Za-z][A-Za-z0-9+.-]*:\/\/[^/?#\s]+(?:\/[^?#]*)?\/verify\/[^?#]*\?(?:.*&)?p=/i;
const JWS_SHAPE = /^[A-Za-z0-9_=-]*\.[A-Za-z0-9_=-]*\.[A-Za-z0-9_=-]*$/;

/** Python's urllib.parse.unquote: %XX runs decoded as UTF-8 (bad bytes replaced), the rest kept. */
function unquote(text) {
  return text.replace(/(?:%[0-9A-Fa-f]{2})+/g, (run) => {
    const bytes = run.match(/%([0-9A-Fa-f]{2})/g).map((part) => parseInt(part.slice(1), 16));
    return new TextDecoder("utf-8").decode(new Uint8Array(bytes));
  });
}

/** The payload in a scanned text; Refused("not_ours" | "check_online") when there is none. */
export function payloadOf(scanned) {
  const text = typeof scanned === "string" ? scanned : "";
  const stripped = text.trim();
  const url = URL_V.exec(stripped);
  if (url && !stripped.toLowerCase().includes("/verify/")) return unquote(url[1]);
  if (LEGACY.test(stripped) || (JWS_SHAPE.test(stripped) && /[a-z]/.test(stripped))) {
    throw new Refused("check_online", "older paper");
  }
  const bare = text.replace(/^\s+/, "").replace(/[\r\n\t]+$/, "");
  if (bare.slice(0, 3).toUpperCase() === "RRQ") return bare;
  throw new Refused("not_ours", "neither a paper's address nor its payload");
}

// ---- the COSE_Sign1 and its claims --------------------------------------------------------------

function unpack(payloadText) {
  const text = payloadText.replace(/^[\r\n\t]+|[\r\n\t]+$/g, "").toUpperCase(); // a camera may lower-case
  if (!text) throw new Refused("damaged", "no base45 text");
  const sign1 = decodeCbor(base45Decode(text));
  if (!(sign1 instanceof Tagged) || sign1.tag !== COSE_SIGN1 || !Array.isArray(sign1.value) || sign1.value.length !== 4) {
    throw new Refused("damaged", "not a COSE_Sign1");
  }
  const [protectedBytes, unprotected, payload, signature] = sign1.value;
  if (![protectedBytes, payload, signature].every((part) => part instanceof Uint8Array)) {
    throw new Refused("damaged", "COSE_Sign1 parts must be byte strings");
  }
  if (!(unprotected instanceof Map) || unprotected.size !== 0) throw new Refused("damaged", "unprotected header");
  const header = decodeCbor(protectedBytes);
  if (!(header instanceof Map) || header.size !== 2 || !header.has(1) || !header.has(4)) {
    throw new Refused("damaged", "the header must hold exactly alg and kid");
  }
  if (header.get(1) !== EDDSA) throw new Refused("not_genuine", "an algorithm other than EdDSA");
  const kid = header.get(4);
  if (!(kid instanceof Uint8Array) || kid.length !== KID_BYTES) throw new Refused("unknown_key", "key id");
  return { protectedBytes, payload, signature, kid: encode64url(kid) };
}

function isInt(value, below) {
  return typeof value === "number" && Number.isInteger(value) && value >= 0 && value < below;
}

function sameKeys(map, keys) {
  return map instanceof Map && map.size === keys.length && keys.every((k) => map.has(k));
}

/** The certificate number of its ten digits, e.g. 2026000123 -> "TRK-2026-000123-K"; null if none. */
export function numberText(digits) {
  const year = Math.floor(digits / 1e6), sequence = digits % 1e6;
  if (year < 1000 || year > 9999 || sequence < 1) return null;
  const ten = String(digits).padStart(10, "0");
  let total = 0;
  for (let i = 0; i < 10; i++) total += (i + 1) * Number(ten[i]);
  const letter = CHECK_ALPHABET[(((-total) % 23) + 23) % 23];
  return `TRK-${ten.slice(0, 4)}-${ten.slice(4)}-${letter}`;
}

/** The claims of a payload in the strict shape of cwt.py, or Refused("not_genuine") (tampered). */
function claimsOf(payload) {
  const body = decodeCbor(payload, "not_genuine");
  const current = sameKeys(body, [CLAIM_ISS, CLAIM_EXP, CLAIM_IAT, CLAIM_OURS]);
  if (!current && !sameKeys(body, [CLAIM_EXP, CLAIM_IAT, CLAIM_OURS])) {
    throw new Refused("not_genuine", "claims of another shape");
  }
  const ours = body.get(CLAIM_OURS);
  if (!sameKeys(ours, current ? [NUMBER, REGISTRATION, COMPLIANT, MAX_OCCUPANTS, KIND] : [NUMBER, REGISTRATION, COMPLIANT, MAX_OCCUPANTS])) {
    throw new Refused("not_genuine", "the trikecert claim of another shape");
  }
  const issuer = current ? body.get(CLAIM_ISS) : null;
  if (current && (typeof issuer !== "string" || [...issuer].length < 1 || [...issuer].length > 200)) {
    throw new Refused("not_genuine", "the issuer must be text");
  }
  const iat = body.get(CLAIM_IAT), exp = body.get(CLAIM_EXP);
  if (!isInt(iat, 2 ** 35) || !isInt(exp, 2 ** 35)) throw new Refused("not_genuine", "dates");
  const digits = ours.get(NUMBER);
  if (!isInt(digits, 1e10) || numberText(digits) === null) throw new Refused("not_genuine", "number");
  const registration = ours.get(REGISTRATION), compliant = ours.get(COMPLIANT), occupants = ours.get(MAX_OCCUPANTS);
  if (typeof registration !== "string" || !registration) throw new Refused("not_genuine", "registration");
  if (typeof compliant !== "boolean") throw new Refused("not_genuine", "verdict");
  if (!isInt(occupants, 100)) throw new Refused("not_genuine", "occupancy");
  if (current && ours.get(KIND) !== (compliant ? 1 : 2)) throw new Refused("not_genuine", "kind");
  return { issuer, iat, exp, digits, number: numberText(digits), registration, compliant, occupants };
}

// ---- the trust bundle (app/trust/bundle.py: read_payload, unpack_bundle, chains_from, open_bundle) ---

const utf8Encoder = new TextEncoder();
const MAX_DATE = 2 ** 35;
const KID_CHARS = 16;

function whole(value, low = 0, high = MAX_DATE) {
  if (!Number.isInteger(value) || value < low || value >= high) throw new Refused("bundle_unreadable", "a number");
  return value;
}

function text(value, size = null) {
  if (typeof value !== "string" || !value || (size !== null && value.length !== size)) {
    throw new Refused("bundle_unreadable", "a text");
  }
  return value;
}

function exactly(object, names) {
  return object && typeof object === "object" && !Array.isArray(object) &&
    Object.keys(object).length === names.length && names.every((name) => Object.hasOwn(object, name));
}

function readKey(value) {
  if (!exactly(value, ["kid", "x", "status", "from", "until", "numbers", "endorsements"])) {
    throw new Refused("bundle_unreadable", "a key of another shape");
  }
  if (!["active", "retired", "compromised"].includes(value.status)) throw new Refused("bundle_unreadable", "status");
  if (value.until !== null) whole(value.until);
  const x = base64url(text(value.x));
  if (!x || x.length !== 32) throw new Refused("bundle_unreadable", "a key must be 32 bytes of Ed25519");
  if (!Array.isArray(value.endorsements)) throw new Refused("bundle_unreadable", "endorsements");
  for (const e of value.endorsements) {
    if (!exactly(e, ["rel", "by", "at", "sig"]) || !["successor", "predecessor"].includes(e.rel)) {
      throw new Refused("bundle_unreadable", "an endorsement of another shape");
    }
    text(e.by, KID_CHARS), whole(e.at), text(e.sig);
  }
  if (value.numbers !== null) {
    if (!Array.isArray(value.numbers) || value.numbers.length !== 2) throw new Refused("bundle_unreadable", "numbers");
    const first = whole(value.numbers[0], 0, 1e10);
    const open = value.numbers[1] === null && value.status === "active";
    const last = open ? null : whole(value.numbers[1], 0, 1e10);
    if (last !== null && last < first) throw new Refused("bundle_unreadable", "numbers");
  }
  text(value.kid, KID_CHARS), whole(value.from);
  return value;
}

/** The bundle's payload checked to the exact shape of version 1; Refused("bundle_unreadable") else. */
export function readPayload(value) {
  const names = ["v", "authority", "issuer", "seq", "made_at", "max_age", "keys", "revoked"];
  const keys = value && typeof value === "object" ? Object.keys(value) : [];
  if (Array.isArray(value) || !names.every((name) => keys.includes(name)) || !keys.every((k) => names.includes(k) || k === "since")) {
    throw new Refused("bundle_unreadable", "a bundle of another shape");
  }
  if (value.v !== 1) throw new Refused("bundle_unreadable", "version");
  if (!Array.isArray(value.keys) || !value.keys.length) throw new Refused("bundle_unreadable", "keys");
  value.keys.forEach(readKey);
  if (new Set(value.keys.map((key) => key.kid)).size !== value.keys.length) throw new Refused("bundle_unreadable", "a key twice");
  text(value.authority), text(value.issuer), whole(value.seq, 0, 2 ** 53), whole(value.made_at), whole(value.max_age, 1);
  if (Object.hasOwn(value, "since")) whole(value.since, 0, 2 ** 53);
  if (!Array.isArray(value.revoked)) throw new Refused("bundle_unreadable", "revoked");
  let previous = -1;
  for (const entry of value.revoked) {
    if (!Array.isArray(entry) || entry.length !== 3 || !["R", "S"].includes(entry[2])) {
      throw new Refused("bundle_unreadable", "a revoked entry");
    }
    if (whole(entry[0], 0, 1e10) <= previous) throw new Refused("bundle_unreadable", "revoked not sorted");
    previous = entry[0];
    whole(entry[1], 10000101, 99991232);
  }
  return value;
}

/** A bundle's JWS read and its signature checked against its own active signing key (no trust yet). */
export async function unpackBundle(jws) {
  const whole = typeof jws === "string" ? jws.trim() : "";
  const parts = whole.split(".");
  if (!whole || parts.length !== 3 || !parts.every(Boolean)) throw new Refused("bundle_unreadable", "not a JWS");
  const [headerBytes, payloadBytes, signature] = parts.map(base64url);
  if (!headerBytes || !payloadBytes || !signature) throw new Refused("bundle_unreadable", "not base64url");
  let header, body;
  try {
    header = JSON.parse(utf8.decode(headerBytes));
    body = JSON.parse(utf8.decode(payloadBytes));
  } catch {
    throw new Refused("bundle_unreadable", "not JSON");
  }
  if (!exactly(header, ["alg", "kid", "typ"]) || header.alg !== "EdDSA" || header.typ !== "trikecert-trust+jws") {
    throw new Refused("bundle_unreadable", "header");
  }
  text(header.kid, KID_CHARS);
  readPayload(body);
  const signer = body.keys.find((key) => key.kid === header.kid);
  if (!signer || signer.status !== "active") throw new Refused("bundle_bad_signature", "signed by no active key of its own");
  const signed = utf8Encoder.encode(`${parts[0]}.${parts[1]}`);
  if (!(await ed25519Verify(base64url(signer.x), signature, signed))) throw new Refused("bundle_bad_signature", "signature");
  return { kid: header.kid, x: signer.x, body };
}

function endorsementText(relation, by, subject, subjectX, at) {
  return utf8Encoder.encode(`trikecert-key-endorsement:1:${relation}:${by}:${subject}:${subjectX}:${at}`);
}

/** True when key `kid` of the bundle is trusted (kid -> x) or reached from one by successor endorsements. */
async function chainsFrom(trusted, body, kid, distrusted) {
  const target = body.keys.find((key) => key.kid === kid);
  if (!target || distrusted.includes(kid)) return false;
  if (Object.hasOwn(trusted, kid)) return trusted[kid] === target.x;
  const reached = new Map(Object.entries(trusted).filter(([k]) => !distrusted.includes(k)));
  let progress = true;
  while (!reached.has(kid) && progress) {
    progress = false;
    for (const key of body.keys) {
      if (reached.has(key.kid) || distrusted.includes(key.kid)) continue;
      for (const e of key.endorsements) {
        if (e.rel !== "successor" || !reached.has(e.by)) continue;
        const sig = base64url(e.sig);
        const message = endorsementText(e.rel, e.by, key.kid, key.x, e.at);
        if (sig && (await ed25519Verify(base64url(reached.get(e.by)), sig, message))) {
          reached.set(key.kid, key.x);
          progress = true;
          break;
        }
      }
    }
  }
  return reached.has(kid);
}

/**
 * A fetched bundle that may replace the one held (open_bundle): its signature checks out, its key is
 * trusted (`trusted`: kid -> x, pinned on first use) or chained from one, it names the held bundle's
 * issuer and authority, and it is not older. Returns {kid, x, body}, or throws Refused(bundle_...).
 */
export async function acceptBundle(jws, trusted, held) {
  const opened = await unpackBundle(jws);
  const distrusted = held ? held.body.keys.filter((key) => key.status === "compromised").map((key) => key.kid) : [];
  const pins = trusted || { [opened.kid]: opened.x }; // trust on first use, from our own origin
  if (!(await chainsFrom(pins, opened.body, opened.kid, distrusted))) {
    throw new Refused("bundle_untrusted_key", "signed by a key no trusted key handed over to");
  }
  if (held) {
    if (opened.body.issuer !== held.body.issuer || opened.body.authority !== held.body.authority) {
      throw new Refused("bundle_other_issuer", "another issuer");
    }
    const older = opened.body.seq < held.body.seq ||
      (opened.body.seq === held.body.seq && opened.body.made_at < held.body.made_at);
    if (older) throw new Refused("bundle_rollback", "older than the one held");
  }
  return opened;
}

function revocation(revoked, digits) {
  let low = 0, high = revoked.length - 1;
  while (low <= high) {
    const middle = (low + high) >> 1;
    const entry = revoked[middle];
    if (entry[0] === digits) return entry;
    if (entry[0] < digits) low = middle + 1;
    else high = middle - 1;
  }
  return null;
}

/**
 * Decide a scanned text with the bundle held (null when none) at `now` (UTC seconds): in exactly the
 * order of BUNDLE-SPEC.md. Returns {code, claims?, bundle?, since?} where since is the yyyymmdd of
 * a revocation.
 */
export async function decide(scanned, held, now) {
  let payloadText;
  try {
    payloadText = payloadOf(scanned);
  } catch (refused) {
    return { code: refused.code };
  }
  if (!held || Object.hasOwn(held.body, "since")) return { code: "no_bundle" };
  const bundle = held.body;
  const seen = { bundle };
  if (now < bundle.made_at - CLOCK_SLACK) return { ...seen, code: "clock_behind" };
  if (now > bundle.made_at + bundle.max_age) return { ...seen, code: "stale" };
  let parts;
  try {
    parts = unpack(payloadText);
  } catch (refused) {
    if (!(refused instanceof Refused)) throw refused;
    return { ...seen, code: refused.code };
  }
  const key = bundle.keys.find((entry) => entry.kid === parts.kid);
  if (!key) return { ...seen, code: "unknown_key" };
  if (key.status === "compromised") return { ...seen, code: "compromised" };
  const x = base64url(key.x);
  const genuine = x && (await ed25519Verify(x, parts.signature, sigStructure(parts.protectedBytes, parts.payload)));
  if (!genuine) return { ...seen, code: "not_genuine" };
  let claims;
  try {
    claims = claimsOf(parts.payload);
  } catch {
    return { ...seen, code: "not_genuine" }; // signed, but not of the strict shape (cwt.py: tampered)
  }
  // What the paper says is shown only once its signature checks out.
  const shown = { ...seen, claims };
  if (claims.issuer !== null && claims.issuer !== bundle.issuer) return { ...shown, code: "not_genuine" };
  if (claims.iat < key.from - CLOCK_SLACK || (key.until !== null && claims.iat > key.until)) {
    return { ...shown, code: "not_genuine" };
  }
  const range = key.numbers;
  if (!range || claims.digits < range[0] || (range[1] !== null && claims.digits > range[1])) {
    return { ...shown, code: "not_genuine" };
  }
  const revoked = revocation(bundle.revoked, claims.digits);
  if (revoked) return { ...shown, code: revoked[2] === "S" ? "superseded" : "revoked", since: revoked[1] };
  if (now >= claims.exp) return { ...shown, code: "expired" };
  return { ...shown, code: claims.compliant ? "certified" : "refusal" };
}
