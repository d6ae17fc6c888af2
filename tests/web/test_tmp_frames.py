import os, time
from pathlib import Path
from fastapi.testclient import TestClient
from web.test_checker_browser import qr_region, worn_print  # noqa
from certificate_helpers import FRONT_HEAVY, FRONT_HEAVY_READINGS, certify, register, weigh


def test_frames(api: TestClient, tmp_path: Path) -> None:
    tag = os.environ["FRAMETAG"]
    n = int(os.environ.get("FRAMEN", "10"))
    register(api)
    register(api, FRONT_HEAVY)
    deadline = time.monotonic() + float(os.environ.get("FRAMESECS", "900"))
    for i in range(n):
        if time.monotonic() > deadline:
            break
        paper = certify(api, weigh(api)) if i % 2 == 0 else certify(api, weigh(api, "KTU-417-XA", FRONT_HEAVY_READINGS))
        folder = tmp_path / f"p{i}"
        frame = qr_region(worn_print(api, paper, folder))
        frame.convert("L").save(f"/tmp/frames/{tag}-{i}-{paper['kind']}.png")
        (Path("/tmp/frames") / f"{tag}-{i}.txt").write_text(paper["qr_payload"])
