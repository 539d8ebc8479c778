"""What a script or a notebook meets first: the compute arguments, the folder it reads, where warnings go."""

import json
import logging
import math
from pathlib import Path

import pytest

import jointwear
from jointwear.config import load_config, updated
from jointwear.schema import ConfigError

pytestmark = pytest.mark.usefixtures("figures_unrendered")  # tests/conftest.py: these tests read results, not pictures

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_an_argument_replaces_the_configs_compute_section(tmp_path):
    """`scheduler=` on a config that names local workers (and the reverse) runs where the argument says; both
    arguments at once are refused."""
    with_workers = updated(load_config(), {"compute.workers": 2})
    study = jointwear.Study(with_workers, out=tmp_path, scheduler="tcp://127.0.0.1:8786")
    assert (study.workers, study.scheduler) == (None, "tcp://127.0.0.1:8786")
    with_scheduler = updated(load_config(), {"compute.scheduler": "tcp://127.0.0.1:8786"})
    study = jointwear.Study(with_scheduler, out=tmp_path, workers=1)
    assert (study.workers, study.scheduler) == (1, None)
    # and config.json records where the calls ran: the config's scheduler it recorded was never used, and a resume
    # from the folder would have connected to it (a user's audit)
    study.simulate(cycles=1)
    recorded = json.loads((tmp_path / "config.json").read_text())["study_config"]["compute"]
    assert (recorded["workers"], recorded["scheduler"]) == (1, None)
    assert jointwear.load_config(tmp_path).compute.scheduler is None
    from types import SimpleNamespace

    from jointwear.compute.executors import scheduler_address

    cluster, client = SimpleNamespace(scheduler_address="tcp://a:1"), SimpleNamespace(scheduler=SimpleNamespace(
        address="tcp://b:2"))
    assert [scheduler_address(s) for s in (None, "tcp://c:3", cluster, client, object())] == [
        None, "tcp://c:3", "tcp://a:1", "tcp://b:2", None]
    assert (jointwear.Study(with_workers, out=tmp_path).workers, jointwear.Study(with_workers).scheduler) == (2, None)
    with pytest.raises(ConfigError, match="not both"):
        jointwear.Study(out=tmp_path, workers=1, scheduler="tcp://127.0.0.1:8786")


def test_results_of_a_folder_that_is_not_there_are_an_error(tmp_path):
    with pytest.raises(FileNotFoundError, match="no study folder"):
        jointwear.load_results(tmp_path / "reslts")
    with pytest.raises(ConfigError, match="has no study results"):
        jointwear.Study(out=tmp_path / "reslts").report()


def test_a_warning_reaches_a_script_without_an_echo(tmp_path, caplog):
    """Without `echo=` the stage summaries go to the logger at INFO (silent by default) and the warnings at WARNING
    (printed by default): a mean 19 standard deviations off its drawing used to pass in silence."""
    shifted = updated(load_config(), {"uncertainty.clearance.mean": 2e-5})
    with caplog.at_level(logging.WARNING, logger="jointwear"):
        found = jointwear.Study(shifted, out=tmp_path).check()
    assert [r.levelno for r in caplog.records] == [logging.WARNING]
    assert "the mean of 'c'" in caplog.records[0].getMessage()
    assert len(found) == 1 and found[0] in caplog.records[0].getMessage()  # returned too, as `check` prints them


def test_check_names_an_unknown_stage_and_gives_its_warnings_again(tmp_path, caplog):
    """check(stages=['simulat', 'bogus']) returned [] as if all were well, and a second check() returned [] after a
    first one that warned."""
    study = jointwear.Study(updated(load_config(), {"uncertainty.clearance.mean": 2e-5}), out=tmp_path)
    with pytest.raises(ConfigError, match="stages: 'simulat' is not a stage \\(did you mean 'simulate'\\?\\)"):
        study.check(stages=["simulat", "bogus"])
    with pytest.raises(ConfigError, match="stages: 'bogus' is not a stage \\(known: simulate, wear, "):
        study.check(stages=["bogus"])
    with caplog.at_level(logging.WARNING, logger="jointwear"):
        first = study.check(stages="reliability")  # one stage by its name
        assert len(first) == 1 and study.check() == first
    assert len(caplog.records) == 1  # told once


def test_resume_and_overwrite_together_are_refused(tmp_path):
    """Both were accepted, and the run then did one of them."""
    with pytest.raises(ConfigError, match="resume/overwrite: give one of them"):
        jointwear.Study(out=tmp_path, resume=True, overwrite=True)


def test_a_config_from_python_is_not_labelled_a_preset(tmp_path):
    data = {"extends": "jin2025_flapping_wing", "name": "mine"}
    jointwear.Study(data, out=tmp_path / "dict").simulate(cycles=1)
    jointwear.Study(None, out=tmp_path / "preset").simulate(cycles=1)
    mine = json.loads((tmp_path / "dict" / "config.json").read_text())
    preset = json.loads((tmp_path / "preset" / "config.json").read_text())
    assert (mine["preset"], mine["source"]) == (None, "python")
    assert (preset["preset"], preset["source"]) == ("jin2025_flapping_wing", "preset")


def test_a_config_loaded_from_a_file_or_preset_records_where_it_came_from(tmp_path):
    """Study(load_config(file)) recorded its source as 'python', as a config built in Python; a validated config is
    read-only, so it is that file's config, recorded as Study(file) records it. A changed copy (updated) is Python's."""
    from pathlib import Path

    from jointwear.config import load_config, updated

    rig = str(Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml")
    assert load_config(rig).origin == rig and load_config(load_config(rig)).origin == rig
    assert updated(load_config(rig), {"wear.block_cycles": 500}).origin is None
    for given in (rig, "flores_slider_crank"):
        assert repr(jointwear.Study(load_config(given), out=tmp_path)) == repr(jointwear.Study(given, out=tmp_path))
    changed = jointwear.Study(updated(load_config(rig), {"wear.block_cycles": 500}), out=tmp_path)
    assert changed.source is None
    # what config.json records, as test_a_config_from_python_is_not_labelled_a_preset reads it
    jointwear.Study(load_config("jin2025_flapping_wing"), out=tmp_path / "preset").simulate(cycles=1)
    written = json.loads((tmp_path / "preset" / "config.json").read_text())
    assert (written["preset"], written["source"]) == ("jin2025_flapping_wing", "preset")


def test_a_folder_with_results_of_another_wear_model_is_warned(tmp_path):
    """A stage run into a folder that holds another model's results: the report would mix the two, so the stage
    moves them aside and says so; another budget (a learning setting) changes no result there and says nothing."""
    lines: list[str] = []
    jointwear.Study(None, out=tmp_path, echo=lines.append).simulate(cycles=1)
    assert lines[0].startswith("simulate: 1 cycle, ")  # not "1 cycles"
    # the crank's speed as the mechanism runs it: 120 without a suffix is 120 rad/s (1,146 rpm), told nowhere else
    assert ", crank at 480 rpm; mean contact force " in lines[0]  # the preset's crank_speed_rpm = 480
    # what a model call costs: its history to the curve's last level in 56 blocks of 10,000 cycles, each settling 1
    # and recording 2
    assert lines[1].startswith("simulate: a wear history of 560,000 cycles (each model call) simulates 168 cycles "), \
        lines[1]
    budget = updated(load_config(), {"reliability.max_calls": 70})
    jointwear.Study(budget, out=tmp_path, echo=lines.append).simulate(cycles=1)
    assert not [line for line in lines if line.startswith("out:")]
    loaded = updated(load_config(), {"mechanism.rod_force": (0.0, -0.05)})
    jointwear.Study(loaded, out=tmp_path, echo=lines.append).simulate(cycles=1)
    (warning,) = [line for line in lines if line.startswith("out:")]
    assert warning.startswith("out: moved the results of simulate (with their tables and figures) to ")
    assert "(changed: mechanism.rod_force)" in warning


def test_a_bushing_worn_through_is_warned(tmp_path):
    """Wear deeper than the bushing's wall (bearing_outer_radius - bearing_radius) leaves the model's range."""
    from pathlib import Path

    own = load_config(Path(__file__).resolve().parents[2] / "examples" / "my_linkage.toml")
    cj = own.clearance_joints[0]
    # (an allowance inside the wall: one beyond it is a check problem of the reliability stage)
    thin = updated(own, {"clearance_joints.B.bearing_outer_radius": cj.bearing_radius + 2e-6,
                         "reliability.allowance_um": 0.3})
    lines: list[str] = []
    result = jointwear.Study(thin, out=tmp_path, echo=lines.append).wear(cycles=200_000)
    assert result.joints[0]["max_wear_mm"] > 2e-3  # deeper than the 2 um wall
    (warning,) = [line for line in lines if "worn through" in line]
    assert "is deeper than its wall (0.002 mm" in warning
    loaded = jointwear.load_results(tmp_path).wear  # wear.json keeps the wall, so the report tells it too
    assert loaded.worn_through() == result.worn_through() and len(loaded.worn_through()) == 1
    html = jointwear.Study(thin, out=tmp_path, echo=lines.append).report().read_text()
    assert "<strong>Worn through.</strong> Joint B&#x27;s bearing wear" in html
    # the journal, past the 0.3 um allowance too, is not what the limit state judges (bearing_max_depth): said so
    assert result.joints[0]["journal"]["max_wear_mm"] > 0.3e-3
    (unjudged,) = [line for line in lines if "which the limit state does not judge" in line]
    assert "joint B's journal wears" in unjudged and "'journal_max_depth' or 'clearance_growth' would" in unjudged
    assert "<strong>Worn past the allowance where it is not judged.</strong>" in html


def test_study_results_have_the_name_their_repr_shows(tmp_path):
    jointwear.Study(None, out=tmp_path).simulate(cycles=1)
    results = jointwear.load_results(tmp_path)
    assert results.name == "jin2025_flapping_wing" and "name='jin2025_flapping_wing'" in repr(results)


def test_a_design_section_left_behind_by_a_variation_only_stops_the_design_stage(tmp_path):
    """A shifted mean can leave the preset's acceptance limits behind: `check` and `design` refuse that, the other
    stages run and say it once (they used to refuse it too, so a plain variation of the preset failed)."""
    shifted = updated(load_config(), {"clearance_joints.A.bearing_material.wear_coefficient": 1.44e-3,
                                      "uncertainty.variables.k_b.mean": 1.44e-3})
    with pytest.raises(ConfigError, match=r"acceptance limits \(0.0013\) must enclose the variable's mean \(0.00144\)"):
        jointwear.Study(shifted, out=tmp_path / "a").check()
    lines: list[str] = []
    study = jointwear.Study(shifted, out=tmp_path / "b", echo=lines.append)
    study.simulate(cycles=1)
    study.simulate(cycles=1)
    (warning,) = [line for line in lines if line.startswith("design:")]
    assert "only the design stage reads the [design] section" in warning
    with pytest.raises(ConfigError, match="must enclose"):
        study.design()


@pytest.mark.parametrize("stage, kwargs, message", [
    ("simulate", {"cycles": 0}, "simulation.cycles: Input should be greater than or equal to 1 \\(got 0\\)"),
    ("simulate", {"cycles": 1, "settle": -1}, "simulation.settle_cycles: Input should be greater than or equal to 0"),
    ("simulate", {"cycles": 2.5}, "simulation.cycles: Input should be a valid integer"),
    ("simulate", {"cycles": "2"}, "cycles: a number is expected, not the string '2'"),
    ("wear", {"cycles": "1000"}, "cycles must be a positive whole number of cycles, got '1000'"),  # was accepted
])
def test_a_stage_argument_is_checked_before_anything_is_written(tmp_path, stage, kwargs, message):
    with pytest.raises(ConfigError, match=message):  # as every check at the boundary (it was a plain ValueError)
        getattr(jointwear.Study(None, out=tmp_path / "out"), stage)(**kwargs)
    assert not (tmp_path / "out").exists()


def test_a_config_changed_in_place_is_validated_again_by_the_study(tmp_path):
    """Its fields are frozen but its lists are plain lists: a None appended gave an AttributeError in every later
    stage; the Study now refuses it, naming the item, and keeps a copy of its own."""
    cfg = load_config()
    study = jointwear.Study(cfg, out=tmp_path)
    assert study.config == cfg and study.config is not cfg
    cfg.clearance_joints.append(None)
    assert len(study.config.clearance_joints) == 1
    with pytest.raises(ConfigError, match=r"clearance_joints\[1\]"):
        jointwear.Study(cfg, out=tmp_path)


def test_a_results_folder_gives_back_the_config_it_ran(tmp_path):
    """config.json keeps the whole validated config (SI): load_config(folder) returns it, so a notebook restarted on
    a folder can rerun or vary the study; `Study(res.config)` on the flat settings failed with unknown keys."""
    cfg = updated(load_config(), {"mechanism.crank_speed_rpm": 420, "reliability.max_calls": 30})
    jointwear.Study(cfg, out=tmp_path).simulate(cycles=1)
    assert load_config(tmp_path) == cfg and load_config(tmp_path / "config.json") == cfg
    assert jointwear.Study(tmp_path / "config.json", out=tmp_path / "again").config == cfg
    (tmp_path / "other.json").write_text("{}")
    with pytest.raises(ConfigError, match="holds no study config"):
        load_config(tmp_path / "other.json")


def test_updated_takes_a_path_as_the_messages_write_it_and_a_driver_by_its_joint():
    """Errors name `mechanism.drivers[0]` and `clearance_joints[0]`, but updated() took only `drivers.0`."""
    own = load_config(EXAMPLES / "my_linkage.toml")
    joint = own.mechanism.drivers[0].joint
    for path in ("mechanism.drivers[0].speed_rpm", f"mechanism.drivers.{joint}.speed_rpm",
                 "mechanism.drivers.0.speed_rpm"):
        assert updated(own, {path: 400.0}).mechanism.drivers[0].speed == pytest.approx(400.0 * 2 * math.pi / 60)
    width = updated(own, {"clearance_joints[0].width_mm": 7.0}).clearance_joints[0].width
    assert width == pytest.approx(7e-3)


def test_the_package_offers_its_lazily_imported_names_to_tab_completion():
    """dir(jointwear) was ['PackageNotFoundError', 'version']: a notebook's completion missed Study."""
    public = [name for name in dir(jointwear) if not name.startswith("_")]
    assert public == sorted(n for n in jointwear.__all__ if not n.startswith("_"))
    assert all(getattr(jointwear, name) is not None for name in public)


def test_a_folder_recorded_in_other_display_units_is_the_same_model(tmp_path):
    """A folder whose config.json shows the hardness in GPa (as older versions wrote it) was said to hold another
    wear model (changed: ...hardness) by a study that shows it in HB: the values are compared in SI now."""
    from jointwear.study.facade import _changed_settings
    from jointwear.study.settings_record import settings_dump, write_dump
    from jointwear.units import PA_PER_HB

    cfg = load_config()
    dump = settings_dump(cfg)
    (tmp_path / "simulate.json").write_text("{}")  # a result, so that the recorded config counts
    old = json.loads(json.dumps(dump))
    for record in old["settings"]:
        if record["unit"] == "HB" and record["value"] is not None:
            record["unit"], record["value"] = "GPa", record["value"] * PA_PER_HB / 1e9
    write_dump(tmp_path, old)
    assert any(r["unit"] == "GPa" and r["name"].endswith("hardness") for r in old["settings"])
    assert _changed_settings(tmp_path, dump["settings"]) == []
    harder = settings_dump(updated(cfg, {"clearance_joints.A.bearing_material.hardness_HB": 400.0}))
    assert _changed_settings(tmp_path, harder["settings"]) == ["clearance_joints[A].bearing_material.hardness"]


def test_a_resume_refused_for_another_model_lists_every_changed_setting(tmp_path, capsys):
    """The refusal named only wear.block_cycles when the curve's end had changed too (its calls' identity holds the
    curve's cycle counts), and its line began 'error: out: ...'."""
    import numpy as np

    from jointwear.cli import main_entry
    from jointwear.compute import EvaluationStore
    from jointwear.compute.store import CallRecord
    from jointwear.study.reliability import store_digest
    from jointwear.study.settings_record import write_settings

    before = load_config()
    write_settings(tmp_path, before)  # as the interrupted study left them: its config beside a store with a call
    with EvaluationStore.open(tmp_path, store_digest(before)) as store:
        store.put("wear_model", CallRecord(x=np.zeros(2), status="ok", reason=None, outputs=np.ones(2), wall_s=1.0))
    config = tmp_path / "changed.toml"
    config.write_text('extends = "jin2025_flapping_wing"\n[wear]\nblock_cycles = 20000\n[reliability]\n'
                      'cycles_stop = 500000\nmax_calls = 99\n', encoding="utf-8")
    assert main_entry(["reliability", str(config), "--out", str(tmp_path), "--resume", "--workers", "1"]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith(f"error: {tmp_path}: the evaluation store there holds calls of another wear model "
                           "(changed: wear.block_cycles, reliability.cycles_stop). Resume with"), line


def test_the_store_survives_a_change_of_what_only_the_wear_and_simulate_stages_read(tmp_path):
    """A longer nominal history (wear.cycles) or other reported peaks refused the resume of a finished study ('holds
    calls of another wear model (changed: wear.cycles)'): a call runs to the curve's last level and returns depths,
    whatever they are. A store keyed before they left the key resumes under its own key; a model change is refused."""
    import numpy as np

    from jointwear.compute import EvaluationStore, config_hash
    from jointwear.compute.store import CallRecord
    from jointwear.study.model_call import WearModelCall
    from jointwear.study.reliability import model_call, store_digest

    before = load_config("flores_slider_crank")
    stage_only = {"wear.cycles": 123_000, "simulation.cycles": 3, "wear.peak_prominence": 0.3,
                  "wear.peak_separation_deg": 40.0}
    after = updated(before, stage_only)
    assert store_digest(after) == store_digest(before)
    assert not any(WearModelCall.depends_on(name) for name in stage_only)
    assert WearModelCall.depends_on("wear.block_cycles") and WearModelCall.depends_on("simulation.rtol")
    former = config_hash(model_call(before).identity(former=True))
    assert former != store_digest(before)
    with EvaluationStore.open(tmp_path, former) as store:  # a store keyed as before
        store.put("wear_model", CallRecord(x=np.zeros(2), status="ok", reason=None, outputs=np.ones(2), wall_s=1.0))
    assert store_digest(before, tmp_path) == former  # read under its own key
    assert EvaluationStore.refusal(tmp_path, store_digest(before, tmp_path), resume=True) is None
    assert store_digest(after, tmp_path) != former  # its former key held wear.cycles, which changed: refused
    changed = updated(before, {"wear.block_cycles": before.wear.block_cycles // 2})
    assert EvaluationStore.refusal(tmp_path, store_digest(changed, tmp_path), resume=True) is not None


def test_an_interrupt_in_python_says_how_to_resume(tmp_path):
    """Ctrl-C in a notebook showed a bare traceback: the command line's 'run again with --resume' was not said."""
    study = jointwear.Study("flores_slider_crank", out=tmp_path, workers=1)
    with pytest.raises(KeyboardInterrupt) as info:
        with study._compute(reuse=False):
            raise KeyboardInterrupt
    (note,) = info.value.__notes__
    assert note == (f"The model calls made so far are kept in {tmp_path / 'evaluations.sqlite'}: run the study again "
                    "with resume=True (--resume) to continue from them.")


def test_the_learnings_progress_line_gives_its_budget(tmp_path):
    """The bar's total grows batch by batch ('12/15'); the learning's call budget was nowhere on the line."""
    from types import SimpleNamespace

    from jointwear.compute import Progress

    study = jointwear.Study(out=tmp_path)
    study._context = SimpleNamespace(cycles=[300_000, 400_000])
    study._progress = Progress(enabled=False)
    study._progress_callback(SimpleNamespace(pf=[0.05, 0.2], cov=[0.01, 0.02], min_u=[1.5, 2.5]))
    assert study._progress.fields["budget"] == f"{study.config.reliability.max_calls} calls"
    # the validation's samples that follow are counted on their own, without the learning's Pf, COV, min U, budget
    study._progress.update(completed=23)
    study._progress_phase("validation samples", 30)
    progress = study._progress
    assert (progress.description, progress.completed, progress.total, progress.fields) == (
        "validation samples", 0, 30, {})


def test_a_mechanism_without_an_allowance_simulates_and_wears(tmp_path):
    # no bushing wall and no [reliability] allowance: the dynamics and the wear need none (simulate crashed on the
    # report settings' allowance); `check` accepted the config, so the stages must too
    rig = Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"
    bare = updated(load_config(str(rig)), {"clearance_joints.0.bearing_outer_radius": None, "wear.cycles": 500})
    assert bare.reliability.allowance is None
    study = jointwear.Study(bare, out=tmp_path)
    study.simulate(cycles=1, settle=0)
    study.wear()
    saved = json.loads((tmp_path / "config.json").read_text(encoding="utf-8"))
    assert "allowance_mm" not in saved


def test_a_folder_whose_lock_cannot_be_written_is_a_config_error(tmp_path, monkeypatch):
    # `run` claims the folder before the stages' own writability check: a read-only folder gave a PermissionError
    # traceback (an immutable folder refuses even root, so the lock's failure is simulated here)
    import filelock

    def refuse(self, *args, **kwargs):
        raise PermissionError(1, "Operation not permitted")

    monkeypatch.setattr(filelock.FileLock, "acquire", refuse)
    (tmp_path / "config.json").write_text("{}", encoding="utf-8")  # an existing folder, as in the report
    with pytest.raises(ConfigError, match="^out: cannot write to .*Operation not permitted"):
        jointwear.Study(out=tmp_path).run()


def test_uniform_modes_range_is_told_per_joint(tmp_path):
    # two joints: the line gave one conformity (the first joint's) without naming it
    six = updated(load_config("watt_six_bar_two_clearances"), {"wear.cycles": 20_000, "wear.block_cycles": 5_000})
    lines: list[str] = []
    jointwear.Study(six, out=tmp_path, echo=lines.append).wear()
    (line,) = [line for line in lines if line.startswith("wear: uniform mode is outside its range here")]
    assert " at joint A, " in line and " at joint E > 1" in line


def test_a_wear_length_given_to_the_stage_silences_the_configs_missing_one(tmp_path):
    # `wear --cycles 2000` on a config without wear.cycles still warned that the wear stage would need them
    rig = Path(__file__).resolve().parents[1] / "wear" / "rigs" / "pendulum.toml"
    config = load_config(str(rig))
    assert config.wear.cycles is None and config.reliability.cycles_stop is None
    lines: list[str] = []
    jointwear.Study(config, out=tmp_path / "given", echo=lines.append).wear(cycles=500)
    assert not [line for line in lines if "will need the number" in line]
    assert [w for w in jointwear.Study(config, out=tmp_path / "check").check() if "will need the number" in w]


@pytest.mark.parametrize("kwargs, needle", [
    ({"overwrite": "false"}, "overwrite: must be True or False"),  # truthy: it discarded 40 stored calls
    ({"resume": "no"}, "resume: must be True or False"),
    ({"resume": 1}, "resume: must be True or False"),
    ({"scheduler": 5}, "scheduler: must be a Dask scheduler's address"),  # refused only after the folder was written
    ({"echo": 5}, "echo: must be a function"),  # the stage wrote its results, then raised TypeError
])
def test_a_study_argument_of_the_wrong_kind_is_refused_before_anything_is_written(tmp_path, kwargs, needle):
    with pytest.raises(ConfigError, match=f"^{needle}"):
        jointwear.Study("flores_slider_crank", out=tmp_path / "out", **kwargs)
    assert not (tmp_path / "out").exists()


def test_numpy_integers_count_as_whole_numbers_and_a_stage_list_must_be_one(tmp_path):
    import numpy as np

    study = jointwear.Study("flores_slider_crank", out=tmp_path / "out", workers=np.int64(2), resume=np.bool_(False))
    assert study.workers == 2 and type(study.workers) is int and study.resume is False
    with pytest.raises(ConfigError, match=r"^stages: a stage name or a list of them \(got 5\)"):
        study.check(5)


def test_a_mapping_with_a_key_that_is_not_a_string_is_refused_by_where():
    for tables, where in (({1: 2}, "1 at the top level"), ({"mechanism": {3: 1}}, "3 in mechanism")):
        with pytest.raises(ConfigError, match=rf"^config: every key of the tables must be a str.*\({where}\)"):
            jointwear.load_config(tables)


def test_a_study_run_again_from_its_folder_or_from_python_keeps_what_its_config_gave(tmp_path):
    """Run again from its results folder, every value of the study counted as given in the config (the report read
    '224 of 224 given' for 128, and `check` called the defaults the config's; a user's audit); so did a config
    loaded in Python and handed to Study, or varied by `updated` (which adds only what it changed)."""
    def given(folder):
        settings = json.loads((folder / "config.json").read_text())["settings"]
        return {s["name"] for s in settings if s["explicit"]}, len(settings)

    jointwear.Study(None, out=tmp_path / "a").simulate(cycles=1)
    first, total = given(tmp_path / "a")
    assert 0 < len(first) < total
    jointwear.Study(str(tmp_path / "a"), out=tmp_path / "b").simulate(cycles=1)
    jointwear.Study(load_config(), out=tmp_path / "c").simulate(cycles=1)
    assert given(tmp_path / "b") == given(tmp_path / "c") == (first, total)
    assert "reliability.n_mc" not in first
    varied = updated(load_config(tmp_path / "a"), {"reliability.n_mc": 1000})
    jointwear.Study(varied, out=tmp_path / "d").simulate(cycles=1)
    assert given(tmp_path / "d") == (first | {"reliability.n_mc"}, total)
