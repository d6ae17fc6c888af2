import json, time, os
from pathlib import Path
from typing import Any
from PIL import Image
from web.test_checker_browser import Camera, camera, guard, load_then_cut, y4m, PHONE  # noqa


def test_hard(camera: Camera, browser_context_args: dict[str, Any], guard: Any, tmp_path: Path) -> None:
    files = json.loads(os.environ["HARD"])
    context = camera.browser.new_context(**{**browser_context_args, "viewport": PHONE, "permissions": ["camera"]})
    guard.watch(context)
    page = context.new_page()
    load_then_cut(context, page)
    out = []
    for i, f in enumerate(files):
        played = y4m(Image.open(f).convert("RGB"), tmp_path / f"v{i}.y4m")
        played.replace(camera.video)
        page.evaluate("document.getElementById('status')?.removeAttribute('data-code')")
        t0 = time.monotonic()
        page.locator("#camera-start").click()
        code = None
        while time.monotonic() - t0 < 6:
            code = page.locator("#status").get_attribute("data-code")
            if code and page.locator("#camera-start").is_visible():
                break
            time.sleep(0.05)
        took = round(time.monotonic() - t0, 2)
        if took >= 6:
            page.locator("#camera-stop").click()
            code = None
        out.append((f, code, took))
    context.close()
    print("\nHARD", json.dumps(out))
