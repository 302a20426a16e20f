import os
import sys
from pathlib import Path

# the tests mirror the code in folders; the helpers they share (rollouts.py) live here
sys.path.insert(0, str(Path(__file__).parent))

# pygame must never need a display or a sound card in the tests
os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")


def pytest_configure(config):
    # slow tests (SB3's `expensive`): deselect them with -m "not slow"
    config.addinivalue_line("markers", "slow: a test that takes more than ~20 s (training a model, a harness run)")
