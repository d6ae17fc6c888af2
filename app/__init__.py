"""trikecert: lateral stability certification of keke, tadpole trikes and quadricycles."""

import gc
from importlib.metadata import PackageNotFoundError, version

# Importing the app makes some 250,000 objects that live as long as the process, and with the
# collector's default thresholds each new batch of them set off a collection that walked all the
# earlier ones again: a tenth of the start of every command, served worker and test run. Collections
# are rarer from here on; a served worker freezes what it holds and goes back to the thresholds found
# (app.main.create_served_app).
GC_THRESHOLDS_FOUND = gc.get_threshold()
gc.set_threshold(50_000, 20, 100)

try:
    __version__ = version("trikecert")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"
