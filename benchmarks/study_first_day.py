"""A real team's first day, on every STEP file of a directory: the whole test loop, as the docs
tell a new user to run it, using only what cadcog drafts and recommends.

For each ``*.step`` / ``*.stp`` file (copied into its own folder under ``--work``):

    setup init → massprops (--report) → plan --for both --json → campaign --swings →
    acquire --simulate --swings → estimate → update --swings (--report) → inertia → check

The weighed mass is the CAD's (the simulated spacecraft is its CAD). ``inertia`` runs on the
inertia plan's hangs when ``plan`` planned one, and is skipped (said so) when ``plan`` says the
swings cannot determine the tensor. ``check`` runs a requirements file holding the model and a
mass requirement. A step passes when it exits 0 (``update``: 0 or 1) and prints no traceback.
One line per step and file, and a summary table (markdown) at the end.

The files are not part of cadcog: fetch public exports of small-satellite hardware (the table in
``docs/spacecraft.md`` names the repositories and commits used) and run

    .venv/bin/python benchmarks/study_first_day.py DIR --work build/first_day
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

CADCOG = [sys.executable, "-m", "cadcog"]


def run(args: list[str], cwd: Path, log: list[str]) -> tuple[int, str, str, float]:
    t0 = time.perf_counter()
    p = subprocess.run([*CADCOG, *args], cwd=cwd, capture_output=True, text=True, check=False)
    dt = time.perf_counter() - t0
    log.append(f"$ cadcog {' '.join(args)}  -> {p.returncode} ({dt:.1f} s)\n{p.stdout}{p.stderr}")
    return p.returncode, p.stdout, p.stderr, dt


def last_line(text: str) -> str:
    lines = [x for x in text.strip().splitlines() if x.strip()]
    return lines[-1][:160] if lines else ""


def one_file(step: Path, work: Path) -> list[dict[str, object]]:
    folder = work / re.sub(r"[^A-Za-z0-9_.-]+", "_", step.stem)
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    model = folder / f"model{step.suffix.lower()}"
    shutil.copyfile(step, model)
    rows: list[dict[str, object]] = []
    log: list[str] = []

    def step_(name: str, args: list[str], ok: tuple[int, ...] = (0,)) -> tuple[int, str]:
        rc, out, err, dt = run(args, folder, log)
        good = rc in ok and "Traceback" not in out + err
        rows.append(
            {
                "file": step.name,
                "step": name,
                "rc": rc,
                "ok": good,
                "s": round(dt, 1),
                "said": last_line(err if rc else out) if not good or rc else "",
            }
        )
        return rc, out

    try:
        rc, _ = step_("setup init", ["setup", "init", model.name])
        if rc:
            return rows
        setup = "model_setup.toml"
        text = (folder / setup).read_text(encoding="utf-8")
        resolve = ["--resolve-overlaps"] if 'overlaps = "resolve"' in text else []
        rc, out = step_(
            "massprops",
            [
                "massprops",
                model.name,
                "--materials",
                "model_materials.toml",
                "--json",
                "--report",
                "views",
                *resolve,
            ],
        )
        if rc:
            return rows
        mass_kg = float(json.loads(out)["mass_kg"])
        rc, out = step_("plan", ["plan", setup, "--for", "both", "--json", "--trials", "2000"])
        if rc:
            return rows
        plan = json.loads(out)
        if plan.get("recommended") is None:  # the plan says why: the loop stops there
            rows.append(
                {
                    "file": step.name,
                    "step": "(stops)",
                    "rc": "-",
                    "ok": True,
                    "s": 0,
                    "said": "plan: " + plan.get("reason", "")[:120],
                }
            )
            return rows
        inertia = plan.get("inertia", {})
        planned = inertia.get("recommended") if isinstance(inertia, dict) else None
        points = ",".join(planned["points"] if planned else plan["recommended"]["points"])
        weigh = ["--weighed-mass-kg", f"{mass_kg:.6g}"]
        step_(
            "campaign",
            [
                "campaign",
                "--setup",
                setup,
                f"--points={points}",
                "--out",
                "r.csv",
                "--swings",
                "s.csv",
            ],
        )
        step_(
            "acquire --simulate",
            [
                "acquire",
                "--simulate",
                "--setup",
                setup,
                f"--points={points}",
                "--out",
                "r2.csv",
                "--swings",
                "s2.csv",
                "--non-interactive",
            ],
        )
        step_("estimate", ["estimate", "r.csv", "--setup", setup, *weigh])
        step_(
            "update --swings",
            [
                "update",
                "r2.csv",
                "--setup",
                setup,
                *weigh,
                "--swings",
                "s2.csv",
                "--report",
                "update_report",
            ],
            ok=(0, 1),
        )
        if planned:
            step_("inertia", ["inertia", "s.csv", "--readings", "r.csv", "--setup", setup, *weigh])
        else:
            rows.append(
                {
                    "file": step.name,
                    "step": "inertia",
                    "rc": "-",
                    "ok": True,
                    "s": 0,
                    "said": "skipped: " + str(inertia.get("refused", "not planned"))[:120],
                }
            )
        (folder / "req.toml").write_text(
            f'name = "first_day"\nmodel_step = "{model.name}"\n'
            'materials = "model_materials.toml"\n'
            + ('overlaps = "resolve"\n' if resolve else "")
            + f"\n[mass]\nmax_kg = {2 * mass_kg:.6g}\nmargin = 0.1\n",
            encoding="utf-8",
        )
        step_("check", ["check", "req.toml"])
    finally:
        (folder / "log.txt").write_text("\n".join(log), encoding="utf-8")
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("directory", type=Path)
    parser.add_argument("--work", type=Path, default=Path("build/first_day"))
    args = parser.parse_args()
    files = sorted(p for p in args.directory.iterdir() if p.suffix.lower() in (".step", ".stp"))
    all_rows = []
    for f in files:
        rows = one_file(f, args.work)
        for r in rows:
            print(
                f"{r['file']:<50} {r['step']:<20} rc {r['rc']!s:<3} "
                f"{'ok  ' if r['ok'] else 'FAIL'} {r['s']:>6} s  {r['said']}",
                flush=True,
            )
        all_rows.extend(rows)
    bad = [r for r in all_rows if not r["ok"]]
    print(f"\n{len(files)} files, {len(all_rows)} steps, {len(bad)} failed")
    print("\n| file | exporter | steps passed | inertia | stops | time (s) |")
    print("|---|---|---|---|---|---|")
    for f in files:
        mine = [r for r in all_rows if r["file"] == f.name]
        ran = [r for r in mine if r["rc"] != "-"]
        inertia = next((r for r in mine if r["step"] == "inertia"), None)
        stop = next((str(r["said"]) for r in mine if r["step"] == "(stops)"), "")
        if inertia is None:
            how = "-"
        elif inertia["rc"] == "-":
            how = "not planned"
        else:
            how = "ok" if inertia["ok"] else "FAIL"
        print(
            f"| {f.name} | {exporter(f)} | {sum(bool(r['ok']) for r in ran)}/{len(ran)} | "
            f"{how} | {stop[:60]} | {sum(float(r['s']) for r in mine):.0f} |"
        )


def exporter(path: Path) -> str:
    """The STEP header's originating system (or preprocessor), shortened."""
    head = path.read_bytes()[:4000].decode("latin-1")
    m = re.search(r"FILE_NAME\s*\((.*?)\);", head, re.S)
    fields = re.findall(r"'([^']*)'", m.group(1)) if m else []
    system = fields[-2].strip() if len(fields) >= 2 else ""
    pre = fields[-3].strip() if len(fields) >= 3 else ""
    return (system or pre or "?")[:40]


if __name__ == "__main__":
    main()
