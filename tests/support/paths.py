"""Where the tests find the repository's files."""

from pathlib import Path

ROOT = Path(__file__).parents[2]
EXAMPLES = ROOT / "examples"
EXAMPLE = EXAMPLES / "rect.yaml"  # the paper's 30 x 60 mm groove
CIRCLE = EXAMPLES / "circle.yaml"
DATA = ROOT / "tests" / "data"
PLUGIN = ROOT / "tests" / "plugin_demo"  # a distribution as pip installs one
