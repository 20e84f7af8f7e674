import os
import subprocess
import sys

# The scripts under test import as modules (tools/ is not a package).
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tools"))


def legend_texts(script, csv, out):
    """Runs the plot `script` on `csv` (writing `out`) and returns its legends' texts, read back from
    the figure it builds, so a test holds the figure's meaning rather than its pixels."""
    probe = os.path.join(os.path.dirname(str(out)), "probe.py")
    with open(probe, "w") as f:
        f.write("import sys, runpy, matplotlib.pyplot as plt\n"
                "texts = []\n"
                "orig = plt.Figure.savefig\n"
                "def grab(self, *a, **k):\n"
                "    texts.extend(t.get_text() for ax in self.axes if ax.get_legend() for t in ax.get_legend().get_texts())\n"
                "    return orig(self, *a, **k)\n"
                "plt.Figure.savefig = grab\n"
                f"sys.argv = [{os.path.basename(script)!r}, '--csv', {str(csv)!r}, '--out', {str(out)!r}]\n"
                f"runpy.run_path({script!r}, run_name='__main__')\n"
                "print('\\n'.join(texts))\n")
    r = subprocess.run(["/usr/bin/python3", probe], capture_output=True, text=True,
                       env={**os.environ, "PYTHONPATH": os.path.dirname(script)})
    assert r.returncode == 0, r.stderr
    return r.stdout.splitlines()
