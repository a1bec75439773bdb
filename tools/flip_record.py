"""The machine-readable line of a run's box flips, which both engines print after their
end-of-run flip note or warning (`dpdnl::engine::lees_edwards::FLIP_RECORD`; the Rust reader is
`dpdnl::io::lammps_log::flip_records`):

    flip_leak: atoms=N jump=1                     (fix flip/momentum, mode jump)
    flip_leak: atoms=N jump=0 momentum=P V=V      (no jump: P and V as the warning prints them)

LAMMPS may append ` (file:line)` to the line; words after the key=value pairs are ignored."""

KEY = "flip_leak:"


def flip_records(log):
    """Every record of a log's text, in order (one per run whose flips put atoms through y): a
    dict with `atoms` (int), `jump` (bool) and, without the jump, `momentum` and `V` (float)."""
    records = []
    for line in log.splitlines():
        line = line.lstrip()
        if not line.startswith(KEY):
            continue
        rec = {}
        for word in line[len(KEY):].split():
            key, eq, value = word.partition("=")
            if not eq:
                break
            rec[key] = value
        try:
            out = {"atoms": int(rec["atoms"]), "jump": rec.get("jump") == "1"}
        except (KeyError, ValueError):
            continue
        for key in ("momentum", "V"):
            if key in rec:
                out[key] = float(rec[key])
        records.append(out)
    return records
