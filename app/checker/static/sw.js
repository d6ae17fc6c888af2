// The /check page's service worker (app/checker/views.py prepends VERSION and KEEP, the files it keeps).
// It keeps the page and its files in a cache named by their digest, so that the page opens with no
// connection; a new version of any of them makes a new worker that fetches them all again. The trust
// bundle is not cached here: the page fetches it itself (a conditional GET) whenever online, checks
// its signature, issuer and sequence, and only then keeps it in the "trikecert-bundle" cache.
const SHELL = `trikecert-check-${VERSION}`;
const BUNDLE_CACHE = "trikecert-bundle";

self.addEventListener("install", (event) => {
  event.waitUntil(
    caches
      .open(SHELL)
      .then((cache) => cache.addAll(KEEP.map((url) => new Request(url, { cache: "no-store" }))))
      .then(() => self.skipWaiting()),
  );
});

self.addEventListener("activate", (event) => {
  event.waitUntil(
    caches
      .keys()
      .then((names) => Promise.all(names.filter((n) => n !== SHELL && n !== BUNDLE_CACHE).map((n) => caches.delete(n))))
      .then(() => self.clients.claim()),
  );
});

self.addEventListener("fetch", (event) => {
  const url = new URL(event.request.url);
  if (event.request.method !== "GET" || url.origin !== self.location.origin || !KEEP.includes(url.pathname)) {
    return; // the bundle and anything else: straight to the network
  }
  if (url.pathname === "/check/") {
    // The page speaks the reader's language (its cookie): online, ask the server each time and keep
    // the answer, so a change of language shows at once; offline, the last page kept.
    event.respondWith(
      fetch(event.request)
        .then(async (fresh) => {
          if (fresh.ok) await (await caches.open(SHELL)).put(url.pathname, fresh.clone());
          return fresh;
        })
        .catch(async () => {
          const kept = await (await caches.open(SHELL)).match(url.pathname);
          if (kept) return kept;
          throw new TypeError("offline and no page kept");
        }),
    );
    return;
  }
  event.respondWith(
    caches.open(SHELL).then(async (cache) => {
      const kept = await cache.match(url.pathname);
      if (kept) return kept;
      const fresh = await fetch(event.request);
      if (fresh.ok) await cache.put(url.pathname, fresh.clone());
      return fresh;
    }),
  );
});
