"""Runs the add-on's pytest suite inside Blender: blender -b --factory-startup --python run.py -- DIR."""
import sys

import pytest

here = sys.argv[sys.argv.index("--") + 1]
sys.exit(pytest.main(["-q", "-p", "no:cacheprovider", here]))
