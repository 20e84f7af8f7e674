import os
import sys

# The scripts under test import as modules (tools/ is not a package).
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tools"))
