"""navlab.numba_start.import_numba_lean: numba imported without PyYAML and with importlib.metadata deferred, and
nothing lost by it: numba still reads a .numba_config.yaml in the working folder, and PyYAML and
importlib.metadata work as usual afterwards. Each check runs in a fresh process, in a folder of its own."""

import json
import os
import subprocess
import sys

IMPORT = '''
import json, sys
from navlab.numba_start import import_numba_lean
import_numba_lean()
import numba
from numba.core import config
metadata = sys.modules.get("importlib.metadata")
deferred = metadata is not None and "entry_points" not in object.__getattribute__(metadata, "__dict__")
state = {"yaml_imported": "yaml" in sys.modules, "numba_has_yaml": config._HAVE_YAML, "opt": config.OPT,
         "metadata_deferred": deferred}
import yaml
from importlib.metadata import version
import numpy
state.update(yaml_works=yaml.safe_load("a: [1, 2]") == {"a": [1, 2]},
             metadata_works=version("numpy") == numpy.__version__)
print(json.dumps(state))
'''


def run(folder):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_OPT"}  # the file's value must not be overridden
    out = subprocess.run([sys.executable, "-c", IMPORT], cwd=folder, env=env, capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_numba_imports_without_yaml_and_metadata_loads_at_first_use(tmp_path):
    got = run(tmp_path)
    assert got["yaml_imported"] is False and got["numba_has_yaml"] is False
    assert got["metadata_deferred"] is True
    assert got["opt"] == 3  # numba's default optimisation level: no configuration read
    assert got["yaml_works"] is True and got["metadata_works"] is True


def test_a_numba_config_file_in_the_working_folder_is_still_read(tmp_path):
    # numba reads the file's values as it reads its environment variables: strings
    (tmp_path / ".numba_config.yaml").write_text("opt: '1'\n")
    got = run(tmp_path)
    assert got["numba_has_yaml"] is True and got["yaml_imported"] is True
    assert got["opt"] == 1  # read from the file, as numba reads it without navlab
    assert got["yaml_works"] is True and got["metadata_works"] is True


def test_it_does_nothing_once_numba_is_imported():
    code = ("import sys, numba\nfrom navlab.numba_start import import_numba_lean\n"
            "before = sys.modules.get('yaml')\nimport_numba_lean()\n"
            "assert sys.modules.get('yaml') is before and 'yaml' in sys.modules\nprint('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "ok"
