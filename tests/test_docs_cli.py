"""No documented option that does not exist, and no option of the command line left undocumented.

The options are read from the click commands themselves (``jointwear.cli.main``), the options of the benchmark
scripts from their argparse calls; the documentation is README.md and every page of docs/.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import click
import pytest

from jointwear.cli import main as cli

ROOT = Path(__file__).resolve().parents[1]
DOC_FILES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SHARED_ANCHOR = "#options-shared-by-the-commands-that-make-model-calls"
# options of third-party programs the docs show, keyed by how the program is named on the same line
OTHER_PROGRAMS = {"dask worker": {"--nworkers", "--nthreads"}, "git describe": {"--dirty"}}
OPTION = re.compile(r"(?<![\w-])(--?[A-Za-z][\w-]*)")
INVOCATION = re.compile(r"(?<![\w./\[-])jointwear(?![\w.\[/-])((?:\s+[^\s|#`;&]+)*)")


GROUP_CTX = click.Context(cli, info_name="jointwear", **cli.context_settings)


def options_of(cmd: click.Command) -> set[str]:
    """Every option string of a command, its help option included (subcommands inherit -h from the group)."""
    ctx = GROUP_CTX if cmd is cli else click.Context(cmd, info_name=cmd.name, parent=GROUP_CTX)
    return {o for p in cmd.get_params(ctx) if isinstance(p, click.Option) for o in (*p.opts, *p.secondary_opts)}


COMMANDS = {name: options_of(cmd) for name, cmd in cli.commands.items()}
GROUP_OPTIONS = options_of(cli)
ALL_CLI_OPTIONS = GROUP_OPTIONS.union(*COMMANDS.values())


def benchmark_options() -> dict[str, set[str]]:
    """Every ``--option`` string passed to ``add_argument`` in each benchmark script."""
    out = {}
    for script in sorted((ROOT / "benchmarks").glob("*.py")):
        opts = set()
        for node in ast.walk(ast.parse(script.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and getattr(node.func, "attr", None) == "add_argument":
                opts |= {a.value for a in node.args if isinstance(a, ast.Constant) and str(a.value).startswith("-")}
        out[f"benchmarks/{script.name}"] = opts
    return out


BENCHMARKS = benchmark_options()


def code_spans(text: str):
    """(line number, text) of every command-like span: lines of fenced non-Python/TOML blocks, inline code."""
    fence, lang = None, ""
    for i, line in enumerate(text.splitlines(), 1):
        m = re.match(r"\s*(```+|~~~+)\s*(\S*)", line)
        if m:
            if fence is None:
                fence, lang = m.group(1), m.group(2)
            elif m.group(1).startswith(fence):
                fence = None
            continue
        if fence is not None:
            if lang not in ("python", "toml", "json", "pycon"):
                yield i, line.lstrip("$ ").split("#")[0] if lang in ("bash", "sh", "console") else line.lstrip("$ ")
            continue
        for span in re.findall(r"`([^`\n]+)`", line):
            yield i, span


def invocations(span: str):
    """(command or None, options given to it) for each ``jointwear ...`` in a span."""
    for m in INVOCATION.finditer(span):
        tokens = [t.strip("[](),.:") for t in m.group(1).split()]
        command, opts = None, []
        for tok in tokens:
            if OPTION.fullmatch(tok.split("=")[0]):
                opts.append(tok.split("=")[0])
            elif command is None and tok:
                command = tok
        yield command, opts


def doc_problems(path: Path) -> list[str]:
    text = path.read_text(encoding="utf-8")
    rel = path.relative_to(ROOT)
    problems = []
    for line_no, span in code_spans(text):
        for command, opts in invocations(span):
            where = f"{rel}:{line_no}: `{span.strip()}`"
            # a lower-case word is a command name; COMMAND, <command> and the like are placeholders
            if command is not None and re.fullmatch(r"[a-z]+", command) and command not in COMMANDS:
                problems.append(f"{where}: no command '{command}'")
                continue
            allowed = COMMANDS[command] | GROUP_OPTIONS if command in COMMANDS else ALL_CLI_OPTIONS
            problems += [f"{where}: '{o}' is not an option of jointwear {command or ''}".rstrip()
                         for o in opts if o not in allowed]
    # any other --option, in code or prose: one of jointwear's, or of a program named in the same paragraph
    # or in a heading above it
    for para_start, para, headings in paragraphs(text):
        scope = para + "\n" + headings
        programs = set().union(*(opts for name, opts in BENCHMARKS.items() if name in scope),
                               *(opts for name, opts in OTHER_PROGRAMS.items() if name in scope))
        for m in re.finditer(r"(?<![\w-])(--[a-z][\w-]*)", para):
            opt = m.group(1)
            if opt not in ALL_CLI_OPTIONS and opt not in programs:
                line_no = para_start + para[:m.start()].count("\n")
                problems.append(f"{rel}:{line_no}: '{opt}' is an option of neither jointwear nor a program "
                                "named in the same paragraph")
    return problems


def paragraphs(text: str):
    """(first line number, text, enclosing headings) of each blank-line separated paragraph."""
    chain: list[tuple[int, str]] = []
    para, start, fenced = [], 1, False
    lines = text.splitlines()
    for i, line in enumerate([*lines, ""], 1):
        if line.lstrip().startswith(("```", "~~~")):
            fenced = not fenced
        heading = None if fenced else re.match(r"(#+)\s+(.*)", line)
        if heading:
            level = len(heading.group(1))
            chain = [h for h in chain if h[0] < level] + [(level, heading.group(2))]
        if line.strip() or fenced:
            if not para:
                start, para_chain = i, "\n".join(h for _, h in chain)
            para.append(line)
        elif para:
            yield start, "\n".join(para), para_chain
            para = []


@pytest.mark.parametrize("path", DOC_FILES, ids=[p.name for p in DOC_FILES])
def test_every_documented_option_exists(path):
    problems = doc_problems(path)
    assert not problems, "\n".join(problems)


def cli_reference_sections() -> dict[str, str]:
    text = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    parts = re.split(r"^## (.+)$", text, flags=re.M)
    return {"": parts[0], **{parts[i].strip(): parts[i + 1] for i in range(1, len(parts), 2)}}


def documented_options(section: str) -> set[str]:
    opts = set()
    for _, span in code_spans(section):
        opts |= {m.group(1) for m in OPTION.finditer(span)}
    return opts


def test_cli_reference_documents_every_command_and_option():
    sections = cli_reference_sections()
    shared_title = next(t for t in sections if t.startswith("Options shared"))
    shared = documented_options(sections[shared_title])
    preamble = documented_options(sections[""])
    assert GROUP_OPTIONS <= preamble, GROUP_OPTIONS - preamble  # --version, -h/--help
    command_sections = {t.removeprefix("jointwear ").strip(): body for t, body in sections.items()
                        if t.startswith("jointwear ")}
    assert set(command_sections) == set(COMMANDS)
    for name, body in command_sections.items():
        documented = documented_options(body) | {"-h", "--help"}  # help: stated once for every command
        if SHARED_ANCHOR in body:
            documented |= shared
        assert documented == COMMANDS[name], (name, "undocumented:", COMMANDS[name] - documented,
                                              "not options:", documented - COMMANDS[name])


def test_the_checks_can_fail(tmp_path):
    """A made-up option, a wrong command's option and an unknown command are each reported."""
    bad = tmp_path / "bad.md"
    bad.write_text("```bash\njointwear run --out r --timeout 5\njointwear wear --samples 3\njointwear levitate\n```\n"
                   "Pass `--no-progress` to be quiet.\n", encoding="utf-8")
    problems = doc_problems_at(bad)
    joined = "\n".join(problems)
    for needle in ("'--timeout'", "'--samples' is not an option of jointwear wear", "no command 'levitate'",
                   "'--no-progress'"):
        assert needle in joined, joined
    assert len(problems) == 5  # --timeout twice: in its invocation and as a stray option


def doc_problems_at(path: Path) -> list[str]:
    global ROOT
    saved, ROOT = ROOT, path.parent
    try:
        return doc_problems(path)
    finally:
        ROOT = saved
