"""The typed settings of model files: the JSON Schema (``pfeie schema``), messages of the
checks the models make (ranges, non-finite numbers, cross-key rules, the slip-weakening
law), the defaults that come from :class:`pfeie.dynamics.DynamicSettings`, and the
command-line overrides (``--duration``, ``--dt``, ``--set``) validated by the same models."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest

import pfeie
from pfeie.cli import main
from pfeie.dynamics import DynamicSettings
from pfeie.errors import InputError
from pfeie.io import ModelFile, json_schema, load_job
from pfeie.io._schema import Analysis
from test_cli import SMALL, _write

ROOT = Path(__file__).resolve().parents[1]
# the model files of the examples (a study file names a model: it is not one)
EXAMPLES = sorted(p for p in (ROOT / "examples").glob("**/*.toml")
                  if "model" not in tomllib.loads(p.read_text()))  # fmt: skip


def _misspelt(data: dict) -> dict:  # type: ignore[type-arg]
    bad = json.loads(json.dumps(data))
    bad.setdefault("analysis", {})["dtt"] = 0.01
    return bad


def test_examples_are_shipped() -> None:
    assert EXAMPLES and ROOT / "examples" / "koyna" / "koyna.toml" in EXAMPLES


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_examples_validate_through_pydantic(path: Path) -> None:
    """Every shipped example validates; a misspelt key does not."""
    data = tomllib.loads(path.read_text())
    ModelFile.model_validate(data)
    with pytest.raises(Exception, match="dtt"):
        ModelFile.model_validate(_misspelt(data))


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_json_schema_validates_examples_and_rejects_a_misspelt_key(path: Path) -> None:
    """The JSON Schema (as written by ``pfeie schema``) accepts every shipped example and
    refuses a misspelt key, a string for a number and a value out of range."""
    jsonschema = pytest.importorskip("jsonschema")
    schema = json_schema()
    validator = jsonschema.Draft7Validator(schema)
    jsonschema.Draft7Validator.check_schema(schema)
    data = tomllib.loads(path.read_text())
    validator.validate(data)
    for bad in (_misspelt(data), {**data, "thickness": "1 m"}, {**data, "thickness": -1.0}):
        assert not validator.is_valid(bad)


def test_schema_command(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``pfeie schema`` prints the schema; ``-o FILE`` writes it; both are the models'."""
    assert main(["schema"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed == json_schema()
    out = tmp_path / "pfeie-model.schema.json"
    assert main(["schema", "-o", str(out)]) == 0
    written = json.loads(out.read_text())
    assert written == printed
    assert written["$schema"].startswith("http://json-schema.org/draft-07")
    assert written["additionalProperties"] is False
    assert set(written["required"]) == {"mesh", "materials", "blocks"}
    analysis = written["$defs"]["Analysis"]["properties"]
    assert set(analysis) == set(Analysis.model_fields)
    assert analysis["dt"]["default"] == DynamicSettings().dt
    assert "default" not in analysis["beta"]  # derived from alpha: no fixed default
    assert "null" not in out.read_text()  # TOML has no null
    assert main(["schema", "-o", str(tmp_path / "no" / "such" / "dir.json")]) == 2


def test_analysis_defaults_are_dynamic_settings() -> None:
    """The [analysis] defaults are DynamicSettings' (one source): in particular β and γ
    are not fixed, so alpha alone gives HHT-α's β = (1 − α)²/4, γ = (1 − 2α)/2."""
    a = Analysis()
    for key in DynamicSettings.model_fields:
        assert getattr(a, key) == getattr(DynamicSettings(), key), key
    assert issubclass(Analysis, DynamicSettings)
    assert Analysis(alpha=-0.1).newmark() == pytest.approx((0.3025, 0.6, -0.1), abs=1e-15)
    assert Analysis(alpha=-0.1).dynamic_settings() == DynamicSettings(alpha=-0.1)


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        (lambda s: s.replace("nu = 0.2", "nu = 0.5"),
         r"materials\.concrete\.nu: expected a number in \(-1, 0\.5\), found 0\.5"),
        (lambda s: s.replace("nu = 0.2", "nu = -1"),
         r"materials\.concrete\.nu: expected a number in \(-1, 0\.5\), found -1"),
        (lambda s: s.replace("friction_angle = 26.565", "friction_angle = 90.0"),
         r"interfaces\.joint\.friction_angle: expected an angle in \[0, 90\) degrees, found 90\.0"),
        (lambda s: s.replace("E = 30e9", "E = inf"),
         r"materials\.concrete\.E: expected a finite number, found inf"),
        (lambda s: s.replace("E = 30e9", "E = nan"),
         r"materials\.concrete\.E: expected a finite number, found nan"),
        (lambda s: s.replace("dt = 0.005", "dt = 1e400"),
         r"analysis\.dt: expected a finite number, found inf"),
        (lambda s: s.replace("[1.0, 2.0]", "[1.0, nan]"),
         r"output\.probes\.top: expected an array of 2 to 3 numbers, each finite, found "
         r"\[1\.0, nan\]"),
        (lambda s: s.replace("[1.0, 2.0]", "[1.0]"),
         r"output\.probes\.top: expected an array of 2 to 3 numbers, found \[1\.0\]"),
        (lambda s: s.replace("[1.0, 2.0]", '[1.0, "a"]'),
         r"output\.probes\.top: expected an array of 2 to 3 numbers, found an array \[1\.0, 'a'\]"),
        (lambda s: s.replace('group = "bottom"', 'group = "bottom"\ncomponents = ["x", "w"]'),
         r"supports\[0\]\.components: expected an array of 'x', 'y', 'z', found \['x', 'w'\]"),
        (lambda s: s.replace('group = "bottom"', 'group = "bottom"\ncomponents = ["z"]'),
         r"supports\[0\]\.components: 'z' in a 2D model"),
        (lambda s: s + "[damping]\nratio = 0.05\nfrequencies = [1.0, 5.0]\nalpha = 0.1\n",
         r"damping: give either ratio and frequencies or alpha and beta, not both"),
        (lambda s: s + "[damping]\nratio = 0.05\nfrequencies = [1.0]\n",
         r"damping\.frequencies: expected an array of 2 numbers, found \[1\.0\]"),
        # the same water on a face, or uplift in a joint, in two tables: applied twice
        (lambda s: s + '[[loads.hydrostatic]]\ngroups = ["up"]\nwater_level = 5.0\n'
         '[[loads.hydrostatic]]\ngroups = ["floor", "up"]\nwater_level = 5.0\n',
         r"loads\.hydrostatic\[1\]\.groups: 'up' is loaded already by loads\.hydrostatic"
         r"\[0\]: it would be loaded twice"),
        (lambda s: s + '[[loads.uplift]]\ninterface = "j"\nheadwater = 5.0\n'
         '[[loads.uplift]]\ninterface = "j"\nheadwater = 5.0\n',
         r"loads\.uplift\[1\]\.interface: 'j' has an uplift already \(loads\.uplift\[0\]\)"),
        # frequencies without a ratio were ignored (no damping, or alpha alone)
        (lambda s: s + "[damping]\nfrequencies = [3.0, 15.0]\n",
         r"damping\.ratio: missing \(required with frequencies"),
        (lambda s: s + "[damping]\nalpha = 0.5\nfrequencies = [3.0, 15.0]\n",
         r"damping\.ratio: missing \(required with frequencies"),
        (lambda s: s.replace("dt = 0.005", "dt = 0.005\nalpha = -0.5"),
         r"analysis\.alpha: expected a number in \[-1/3, 0\], found -0\.5"),
        (lambda s: s.replace("dt = 0.005", "dt = 0.005\nalpha = -0.1\nlarge_rotation = true"),
         r"analysis: large_rotation runs on the nonsmooth-alpha or Moreau-Jean scheme or on "
         r"the Newmark rule \(alpha = 0, no rho_inf\)"),
        (lambda s: s.replace("dt = 0.005", "dt = 0.005\nform = \"moving\""),
         r"analysis\.form: expected one of 'relative', 'absolute', found 'moving'"),
        (lambda s: s.replace("dt = 0.005", "dt = 0.005\nstatic = 1"),
         r"analysis\.static: expected a boolean, found an integer 1"),
        (lambda s: s.replace('folder = "out"', 'folder = "out"\nevery = 0'),
         r"output\.every: expected an integer > 0, found 0"),
        (lambda s: s.replace('folder = "out"', 'folder = "out"\nevery = 2.0'),
         r"output\.every: expected an integer, found a number 2\.0"),
        (lambda s: s.replace("[[supports]]", "[supports]"),
         r"supports: expected an array of tables \(\[\[supports\]\]\), found a table"),
        (lambda s: s.replace('title = "two blocks"', 'title = "two blocks"\nmesh = "x.msh"'),
         r"not valid TOML"),
        (lambda s: s.replace('title = "two blocks"', 'title = "two blocks"\ncolour = 1'),
         r"colour: unknown key; expected one of: analysis, blocks, damping, ground_motion, "
         r"interfaces, loads, materials, mesh, output, plane, supports, thickness, title"),
        (lambda s: s.replace("friction_angle = 26.565", "friction_angle = 26.565\n"
                             "law = \"slip-weakening\""),
         r"interfaces\.joint\.weakening_distance: missing \(required with law = "
         r"'slip-weakening'\)"),
        (lambda s: s.replace("friction_angle = 26.565", "friction_angle = 26.565\n"
                             "weakening_distance = 0.01"),
         r"interfaces\.joint\.weakening_distance: only with law = 'slip-weakening' "
         r"\(law is 'mohr-coulomb'\)"),
        (lambda s: s.replace("friction_angle = 26.565", "friction_angle = 26.565\n"
                             "law = \"rate-and-state\""),
         r"interfaces\.joint\.law: expected one of 'mohr-coulomb', 'slip-weakening', found "
         r"'rate-and-state'"),
        (lambda s: s.replace("friction_angle = 26.565", "friction_angle = 26.565\n"
                             "law = \"slip-weakening\"\nweakening_distance = -0.01"),
         r"interfaces\.joint\.weakening_distance: expected a number in \(0, 1e\+06\] m, "
         r"found -0\.01"),
    ],
)  # fmt: skip
def test_model_file_checks(tmp_path: Path, edit, match: str) -> None:  # type: ignore[no-untyped-def]
    p = _write(tmp_path, edit(SMALL))
    with pytest.raises(InputError, match=match) as err:
        load_job(p)
    assert str(err.value).startswith(str(p))
    assert main(["check", str(p)]) == 2


def test_slip_weakening_interface_builds_its_law(tmp_path: Path) -> None:
    """``law = "slip-weakening"`` builds a :class:`pfeie.SlipWeakening` with the peak and
    residual friction angles and the weakening distance of the file; the distance is
    refused for a Mohr-Coulomb joint and required for slip weakening."""
    text = SMALL.replace("friction_angle = 26.565", "friction_angle = 35.0\n"
                         "residual_friction_angle = 25.0\nlaw = \"slip-weakening\"\n"
                         "weakening_distance = 0.01")  # fmt: skip
    job = load_job(_write(tmp_path, text))
    law = job.model.interfaces[0].joint
    assert isinstance(law, pfeie.SlipWeakening)
    assert (law.phi, law.phi_r, law.dc) == (35.0, 25.0, 0.01)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["--duration", "-1"], "analysis.duration (from --duration -1): expected a number > 0 s, "
         "found -1"),
        (["--duration", "nan"], "analysis.duration (from --duration nan): expected a finite "
         "number, found nan"),
        (["--duration", "long"], "analysis.duration (from --duration long): expected a number, "
         "found a string 'long'"),
        (["--duration", "1e12"], "analysis.duration (from --duration 1e12): duration "
         "1000000000000.0 s is 2e+14 steps of 0.005 s: too many"),
        (["--dt", "0"], "analysis.dt (from --dt 0): expected a number in (0, 10] s, found 0"),
        (["--set", "analysis.alpha=-0.5"], "analysis.alpha (from --set analysis.alpha=-0.5): "
         "expected a number in [-1/3, 0], found -0.5"),
        (["--set", "analysis.alpa=-0.1"], "analysis.alpa (from --set analysis.alpa=-0.1): "
         "unknown key; expected one of: alpha, backend"),
        (["--set", "ground_motion[3].scale=2"], "ground_motion[3].scale (from --set "
         "ground_motion[3].scale=2): no item 3 (the file has 1)"),
        (["--set", "analysis.alpha"], "--set analysis.alpha: expected KEY=VALUE"),
    ],
)  # fmt: skip
def test_command_line_settings_are_validated(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], match: str
) -> None:
    """Invalid --duration, --dt or --set: exit 2 and a ``pfeie: error:`` line that names
    the option and the expectation, never a traceback."""
    p = _write(tmp_path, SMALL)
    for cmd in ("check", "run"):
        assert main([cmd, str(p), *args]) == 2
        err = capsys.readouterr().err
        assert err.startswith("pfeie: error: ") and match in err, err
        assert "Traceback" not in err
    assert not (tmp_path / "out").exists()


def test_command_line_settings_reach_the_run(tmp_path: Path) -> None:
    """--duration, --dt and --set change the run; the stored settings show the scheme and
    θ chosen on the command line."""
    from pfeie.io import Results

    p = _write(tmp_path, SMALL)
    assert main(["run", str(p), "--quiet", "--duration", "0.1", "--dt", "0.01",
                 "--set", "analysis.scheme=moreau-jean", "--set", "analysis.theta=0.8",
                 "--set", "output.folder=run2",
                 "--set", "output.paraview=false"]) == 0  # fmt: skip
    with Results(tmp_path / "run2" / "results.h5") as res:
        assert res.time[-1] == pytest.approx(0.1) and len(res.time) == 11
        a = json.loads(res.meta["analysis"]) if isinstance(res.meta["analysis"], str) else (
            res.meta["analysis"])  # fmt: skip
    assert a["scheme"] == "moreau-jean" and a["theta"] == 0.8
    assert not (tmp_path / "run2" / "blocks.xdmf").exists()


def test_summary_counts_steps_once(tmp_path: Path) -> None:
    """The model summary's step count is DynamicSettings.steps (also without records)."""
    p = _write(tmp_path, SMALL, duration=0.6)
    job = load_job(p)
    assert job.summary()["steps"] == DynamicSettings(dt=0.005).steps(0.6) == 120
    text = SMALL.replace('[[ground_motion]]\nfile = "pulse.csv"\nunits = "g"\n', "")
    job = load_job(_write(tmp_path, text, duration=0.3))
    assert not job.records and job.summary()["steps"] == 60
