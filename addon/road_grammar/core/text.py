"""Words and numbers for reports and panels."""


def plural(count, word):
    """'1 rule', '3 rules', '2 vertices', '1,200 streets'."""
    count = int(count)
    if count == 1:
        return "1 " + word
    word = word[:-len("vertex")] + "vertices" if word.endswith("vertex") else word + "s"
    return "{:,} {}".format(count, word)


def tries(count):
    return "1 try" if count == 1 else "{:,} tries".format(count)


def rejections(report):
    """Why the tries of ggg.grow_region failed: '12 outside, 3 crossing, 40 crowded'."""
    parts = ["{:,} outside".format(report["rejected_outside"]), "{:,} crossing".format(report["rejected_crossing"]),
             "{:,} crowded".format(report["rejected_crowded"])]
    if report.get("rejected_off_grid"):
        parts.append("{:,} off the grid".format(report["rejected_off_grid"]))
    if report.get("rejected_small_block"):
        parts.append("{:,} closing a sliver".format(report["rejected_small_block"]))
    return ", ".join(parts)


def compact(number):
    """A count in at most 5 characters: 950, 9999, 12.3k, 456k, 1.2M."""
    number = float(number)
    if abs(number) < 10_000:
        return "{:.0f}".format(number)
    if abs(number) < 100_000:
        return "{:.1f}k".format(number / 1e3)
    if abs(number) < 1_000_000:
        return "{:.0f}k".format(number / 1e3)
    return "{:.1f}M".format(number / 1e6)


def wrap(text, width=48):
    """``text`` as lines of at most ``width`` characters, broken between words (a word
    longer than that is a line of its own)."""
    lines = []
    line = ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = word if not line else line + " " + word
    if line:
        lines.append(line)
    return lines


def learned_summary(name, stats, seconds):
    """One line about a grammar learned from ``name``, from the ``stats`` of ggg.learn."""
    roundtrip = stats.get("roundtrip", {})
    size = stats.get("bytes", {})
    axiom = stats.get("axiom", {})
    if roundtrip.get("edges_equal"):
        edges = "same edges"
    else:
        edges = "{:,} edges missing, {:,} extra".format(roundtrip.get("missing_edges", 0),
                                                         roundtrip.get("extra_edges", 0))
    return ("Learned a grammar of {} ({}) in {:.2f} s: {}, {}, {}; axiom {}, {}; {:,} -> {:,} bytes; round trip: "
            "{}, max error {:.3g} m (mean {:.3g} m)").format(
        name, stats.get("mode", "?"), seconds, plural(stats.get("rules", 0), "rule"),
        plural(stats.get("levels", 0), "level"), plural(stats.get("instances", 0), "instance"),
        plural(axiom.get("vertices", 0), "vertex"), plural(axiom.get("edges", 0), "edge"),
        size.get("original", 0), size.get("encoded", 0), edges, roundtrip.get("max_displacement_m", 0.0),
        roundtrip.get("mean_displacement_m", 0.0))


def size_lines(stats):
    """The sizes of a learned grammar against its graph, from the ``stats`` of ggg.learn, as
    panel lines: the JSON and CBOR files, then what each pass of learning saved."""
    size = stats.get("bytes", {})
    lines = []
    for label, original, encoded in (("JSON", "original", "encoded"), ("CBOR", "original_cbor", "encoded_cbor")):
        if size.get(original):
            lines.append("{}: {:,} \u2192 {:,} bytes ({:.2f}\u00d7)".format(
                label, size[original], size.get(encoded, 0), size.get(encoded, 0) / size[original]))
    # Where the CBOR bytes go, largest first: what the grammar stores against the graph's
    # positions and edges.
    for label, key in (("Graph", "original"), ("Grammar", "encoded")):
        parts = size.get("parts_cbor", {}).get(key, {})
        shown = [(name, count) for name, count in sorted(parts.items(), key=lambda p: (-p[1], p[0])) if count > 0]
        if shown:
            lines.append("{} CBOR: {}".format(label, ", ".join("{} {}".format(name.replace("_", " "), compact(count))
                                                             for name, count in shown)))
    for level in stats.get("per_level", []):
        saved = level.get("bytes_saved", 0)
        lines.append("Pass {}: {}, {} {} bytes".format(level.get("level", 0), plural(level.get("rules", 0), "rule"),
                                                       "saves" if saved >= 0 else "costs", compact(abs(saved))))
    return lines
