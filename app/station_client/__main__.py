"""`python -m app.station_client` is `trikecert-station`."""

from app.station_client.cli import main

raise SystemExit(main())
