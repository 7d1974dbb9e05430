#!/usr/bin/env python3
"""PETSc's -log_view report as the benchmark scripts read it: the stage times of its
'Summary of Stages', the events of each stage (count, time, flop) and how often one event
ran. Text in, numbers out: no fsiopt run starts here."""
import re


def parse_stages(stdout_text):
    """{stage name: seconds} from the 'Summary of Stages' of -log_view."""
    stages, inside = {}, False
    for line in stdout_text.splitlines():
        if line.startswith("Summary of Stages"):
            inside = True
            continue
        if inside:
            m = re.match(r"\s*\d+:\s+(.+?):\s+([-+0-9.eE]+)\s+[0-9.]+%", line)
            if m:
                stages[m.group(1).strip()] = float(m.group(2))
            elif stages and not line.strip():
                break
    return stages


def parse_stage_event_table(stdout_text):
    """{stage name: {event name: (count, seconds (max over ranks), flop (max over ranks))}}
    from -log_view's event table."""
    events, stage = {}, None
    for line in stdout_text.splitlines():
        if line.startswith("Object Type") and events:
            break   # the object tables repeat the stage headers
        m = re.match(r"--- Event Stage \d+: (.+)$", line)
        if m:
            stage = m.group(1).strip()
            events.setdefault(stage, {})
            continue
        fields = line.split()
        if stage and len(fields) > 6 and fields[1].isdigit():
            try:
                events[stage][fields[0]] = (int(fields[1]), float(fields[3]), float(fields[5]))
            except ValueError:
                pass
    return events


def parse_stage_events(stdout_text):
    """{stage name: {event name: seconds (max over ranks)}} from -log_view's event table."""
    return {stage: {name: e[1] for name, e in table.items()}
            for stage, table in parse_stage_event_table(stdout_text).items()}


def parse_event_count(stdout_text, event):
    """how many times -log_view's event `event` ran, summed over the stages (None when absent)"""
    total, seen = 0, False
    for line in stdout_text.splitlines():
        fields = line.split()
        if len(fields) > 2 and fields[0] == event and fields[1].isdigit():
            total, seen = total + int(fields[1]), True
    return total if seen else None


if __name__ == "__main__":   # a module: --help (or no argument) prints what it is for
    from fsiopt_tables import module_help
    module_help(__doc__, "scripts/bench.py, bench_runs.py, cost_growth.py, strong_scaling.py and variant_cost.py")
