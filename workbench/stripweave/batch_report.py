"""What `stripweave batch` writes about its models: OUT/summary.json, OUT/summary.md,
OUT/index.html, and its progress lines.

Input: the finished summary entries (batch.py): {"model", "status", "error", "time_s",
"peak_memory_mb", "report" (report.json's content or None), "out" (OUT/<out> holds the
model's outputs)}. A figure that an entry's report lacks (an older report, a failed fit,
no --step) reads "n/a", never a number that flatters: in particular the fit's maximum is
the two-sided one, not the one-sided max_deviation of reports before issue 16.
"""
import html
import json
import os
import urllib.parse

NA = "n/a"
DEFECT_WORDS = {"non_quad_patches": "non-quad", "overlapping_edges": "overlapping", "valence2_vertices": "valence-2",
                "high_valence_vertices": "valence>6", "creased_patches": "creased",
                "degenerate_patches": "degenerate", "uncovered_triangles": "uncovered triangles"}
COLUMNS = ("model", "input triangles", "solver triangles", "time s", "peak MB", "valid", "clean", "defects",
           "strips", "patches", "irregular vertices", "corner dev. mean / p95 deg", "fit max / tolerance",
           "coverage", "status")


def write_summary(out, entries):
    """(Re)write OUT/summary.json, summary.md and index.html for the finished entries;
    each file is replaced whole, so a reader never sees half of one."""
    summary = {"format": "stripweave-batch", "version": 1, "models": entries}
    _replace(os.path.join(out, "summary.json"), json.dumps(summary, indent=1) + "\n")
    _replace(os.path.join(out, "summary.md"), format_markdown(entries))
    _replace(os.path.join(out, "index.html"), format_html(entries, out))


def _replace(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


# --- one entry's figures, as text --------------------------------------------------------

def _number(value, fmt):
    return NA if value is None else format(value, fmt)


def _yes_no(value):
    return NA if value is None else ("yes" if value else "no")


def _defects(report):
    defects = report.get("defects")
    if not isinstance(defects, dict):
        return NA
    total = sum(int(n) for n in defects.values())
    kinds = ", ".join(f"{n} {DEFECT_WORDS.get(k, k)}" for k, n in defects.items() if n)
    return f"{total} ({kinds})" if total else "0"


def _irregular(report):
    counts = report.get("irregular_vertices")
    if not isinstance(counts, dict):
        return NA
    total = sum(int(n) for n in counts.values())
    listed = ", ".join(f"{n} of valence {v}" for v, n in counts.items())
    return f"{total} ({listed})" if total else "0"


def _corner_deviation(report):
    """mean / p95 over the quad patches' corners, and where some patches are no quad, how many
    are (the figures leave those out) and the mean with each counted as four corners 90
    degrees off (job._corner_coverage)."""
    d = report.get("corner_deviation_deg") or {}
    text = f"{_number(d.get('mean'), '.1f')} / {_number(d.get('p95'), '.1f')}"
    quads, patches = d.get("quads"), d.get("patches")
    if isinstance(quads, int) and isinstance(patches, int) and quads < patches:
        text += f" ({patches - quads} no quad: all {_number(d.get('mean_all_patches'), '.1f')})"
    return text


def _fit(report):
    """(two-sided max / tolerance [met|not met], coverage): n/a without a two-sided fit. A fit
    of the components a red region leaves alone (fit.set_aside_components: the run failed,
    the STEP holds part of the model) shows its whole-part figures, marked partial."""
    fit = report.get("fit")
    if not isinstance(fit, dict) or ("error" in fit and not fit.get("set_aside_components")):
        return NA, NA
    sides = (fit.get("max_deviation_source_to_patches"), fit.get("max_deviation_patches_to_source"))
    deviation = NA if None in sides else format(max(sides), ".3g")
    text = f"{deviation} / {_number(fit.get('tolerance'), '.3g')}"
    if "tolerance_met" in fit:
        text += " met" if fit["tolerance_met"] else " not met"
    if fit.get("set_aside_components"):
        text += f" (partial: components {', '.join(str(c) for c in fit['set_aside_components'])} set aside)"
    coverage = fit.get("coverage")
    return text, NA if coverage is None else f"{100.0 * coverage:.1f}%"


def _status(entry):
    return entry["status"] if entry["status"] == "ok" else f"{entry['status']}: {entry['error']}"


def cells(entry):
    """The summary table's row of an entry: one text per COLUMNS."""
    r = entry.get("report") or {}
    fit, coverage = _fit(r)
    return [entry["model"], _number(r.get("input_triangles"), "d"), _number(r.get("solver_triangles"), "d"),
            _number(entry.get("time_s"), ".1f"), _number(entry.get("peak_memory_mb"), ".0f"),
            _yes_no(r.get("valid")), _yes_no(r.get("clean")), _defects(r), _number(r.get("strips"), "d"),
            _number(r.get("patches"), "d"), _irregular(r), _corner_deviation(r) if r else NA, fit, coverage,
            _status(entry)]


def totals(entries):
    """The totals line: statuses, valid and clean counts, time and memory."""
    counts = {s: sum(e["status"] == s for e in entries) for s in ("ok", "error", "timeout", "crash")}
    reports = [e["report"] for e in entries if e.get("report")]
    valid = sum(bool(r.get("valid")) for r in reports)
    clean = (f"{sum(bool(r.get('clean')) for r in reports)} clean" if any("clean" in r for r in reports)
             else f"clean {NA}")
    seconds = sum(e["time_s"] or 0.0 for e in entries)
    peak = max((e["peak_memory_mb"] or 0.0 for e in entries), default=0.0)
    return (f"{len(entries)} model{'' if len(entries) == 1 else 's'}: {counts['ok']} ok, {counts['error']} error, {counts['timeout']} timeout, "
            f"{counts['crash']} crash; {valid} valid, {clean}; {seconds:.1f} s in all (summed over the models), "
            f"largest peak memory {peak:.0f} MB")


def format_progress(n, total, entry):
    """One stderr line per finished model: n/total, model, status, time, key figures."""
    r = entry.get("report") or {}
    figures = []
    if r:
        figures.append(f"{'valid' if r.get('valid') else 'NOT valid'}"
                       + ("" if "clean" not in r else (", clean" if r["clean"] else ", not clean")))
        figures.append(f"{r.get('patches', NA)} patch{'' if r.get('patches') == 1 else 'es'}")
        fit, coverage = _fit(r)
        if fit != NA:
            figures.append(f"fit {fit}, coverage {coverage}")
    text = "ok" if entry["status"] == "ok" else f"{entry['status'].upper()}: {entry['error']}"
    return (f"[{n}/{total}] {entry['model']}: {text} in {_number(entry.get('time_s'), '.1f')} s, "
            f"{_number(entry.get('peak_memory_mb'), '.0f')} MB" + ("; " + "; ".join(figures) if figures else ""))


# --- summary.md ----------------------------------------------------------------------------

def format_markdown(entries):
    def row(texts):
        return "| " + " | ".join(t.replace("|", "\\|").replace("\n", " ") for t in texts) + " |"

    lines = ["# stripweave batch", "", row(COLUMNS), row(["---"] * len(COLUMNS))]
    lines += [row(cells(e)) for e in entries]
    lines += ["", f"**Totals:** {totals(entries)}", ""]
    return "\n".join(lines)


# --- index.html ----------------------------------------------------------------------------

STYLE = """body{font-family:sans-serif;margin:1em;background:#fff;color:#222}
.sheet{display:flex;flex-wrap:wrap;gap:12px}
.card{border:1px solid #bbb;border-radius:6px;padding:8px;width:380px}
.card.failed{border:2px solid #c00}
.card h2{font-size:15px;margin:0 0 4px 0;word-break:break-all}
.pictures{display:flex;gap:4px}.pictures img{width:186px;height:auto;border:1px solid #ddd}
.missing{width:186px;height:100px;display:flex;align-items:center;justify-content:center;background:#f4f4f4;color:#888}
.figures{display:grid;grid-template-columns:auto 1fr;column-gap:8px;font-size:11px;margin-top:4px}
.figures span:nth-child(odd){color:#666}
.status{font-weight:bold;color:#070}.failed .status{color:#c00}"""


def _picture(out, folder, name):
    if os.path.exists(os.path.join(out, folder, name)):
        link = urllib.parse.quote(f"{folder}/{name}")
        return f'<a href="{link}"><img src="{link}" alt="{html.escape(name)}"></a>'
    return f'<div class="missing">no {html.escape(name)}</div>'


def _card(out, entry):
    texts = cells(entry)
    failed = entry["status"] != "ok"
    rows = "".join(f"<span>{html.escape(k)}</span><span>{html.escape(v)}</span>"
                   for k, v in zip(COLUMNS[1:-1], texts[1:-1]))
    folder = entry.get("out") or ""
    return (f'<div class="card{" failed" if failed else ""}"><h2>{html.escape(entry["model"])}</h2>'
            f'<div class="status">{html.escape(texts[-1])}</div>'
            f'<div class="pictures">{_picture(out, folder, "preview.png")}{_picture(out, folder, "deviation.png")}</div>'
            f'<div class="figures">{rows}</div></div>')


def format_html(entries, out):
    """A contact sheet: per model its preview.png and deviation.png (links relative to
    OUT), its figures and its status, failures in red."""
    cards = "\n".join(_card(out, e) for e in entries)
    return (f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>stripweave batch</title>'
            f"<style>{STYLE}</style></head><body><h1>stripweave batch</h1>"
            f"<p>{html.escape(totals(entries))}</p><div class=\"sheet\">\n{cards}\n</div></body></html>\n")
