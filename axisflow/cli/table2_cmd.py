"""``axisflow table2``: the paper's Table 2 from a recording of planner runs on the axis."""

from __future__ import annotations

import argparse

from ..acquisition.wire.keys import DEFAULT_PREFIX, AxisKeys


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "table2",
        help="Table 2 from a recording: planned (E_th) against measured (E_exp) energy per run",
        description="Read a recording of `axisflow planner` runs (plan records, move status, measured "
        "samples, setpoints) and print the paper's Table 2 per run: T, E_th, E_exp = ∫τ_m·ω_m dt of "
        "the measured torque and motor speed under the plans' energy accounting, E%, t_opt and the idle "
        "ticks between moves. Writes DIR/table2.md and DIR/table2.json (existing ones only with "
        "--overwrite). A chunk of the recording that cannot be read is skipped and named; a move that "
        "lost samples with it has no measured energy.",
    )
    p.add_argument("recording", metavar="LOG.mcap", help="recording of the planner's runs")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory (created if missing)")
    p.add_argument("--overwrite", action="store_true", help="replace an earlier table in DIR")
    p.add_argument("--label", default=None, help="only the runs with this plan label (default: all)")
    p.add_argument(
        "--axis",
        default=None,
        help="the axis of a recording of several (a cell's: a0, a1, …); default: the recording's only axis "
        "(a recording of several without --axis is refused with the list of its axes)",
    )
    p.add_argument(
        "--prefix", default=None, help=f"key prefix of the axis (default: any; ours is {DEFAULT_PREFIX})"
    )
    p.add_argument("--json", action="store_true", help="print table2.json instead of the table")
    p.add_argument(
        "--per-move",
        action="store_true",
        help="also write DIR/moves.csv and DIR/moves.json: each move's E_th, E_exp, E%% and the parameter "
        "version its plan used, in the order the moves ran",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..acquisition.logs.reader import check_mcap
    from ..acquisition.logs.recorded_axes import choose_axis
    from ..experiment.per_move import write_move_energies
    from ..experiment.table2 import move_energies, recorded_runs, table_of_runs
    from ..experiment.table2_markdown import write_table2
    from ..model.files import check_output_files

    recording = check_mcap(args.recording)
    names = ("table2.md", "table2.json") + (("moves.csv", "moves.json") if args.per_move else ())
    out = check_output_files(args.out, names, inputs=[recording], overwrite=args.overwrite)
    axis = choose_axis(recording, args.axis, args.prefix)
    runs, accounting = recorded_runs(args.recording, AxisKeys(axis.axis, axis.prefix), args.label)
    table = table_of_runs(runs, accounting, "Table 2, on the axis", str(args.recording))
    json_path, md_path = write_table2(table, out)
    if args.per_move:
        write_move_energies(move_energies(runs), out)
    print((json_path if args.json else md_path).read_text(), end="")
    if not args.json:
        extra = f", {out / 'moves.csv'} and {out / 'moves.json'}" if args.per_move else ""
        print(f"\nwrote {md_path}, {json_path}{extra}")
    return 0
