"""A framed SVG plot panel and helpers shared by the plotting scripts (standard library only)."""


def moving_average(values, window):
    """Mean of each value and up to window - 1 before it."""
    out, acc = [], 0.0
    for i, v in enumerate(values):
        acc += v
        if i >= window:
            acc -= values[i - window]
        out.append(acc / min(i + 1, window))
    return out


def axes(left, right, top, height, x_max, lo, hi, title):
    """Frame, title and three y labels of a panel spanning x in [0, x_max] and y in [lo, hi].

    Returns (svg parts, px, py): px and py map data coordinates to pixels.
    """
    if hi - lo < 1e-9:
        hi = lo + 1
    x_max = x_max if x_max > 0 else 1

    def px(v):
        return left + (right - left) * v / x_max

    def py(v):
        return top + height - height * (v - lo) / (hi - lo)

    parts = [f'<rect x="{left}" y="{top}" width="{right-left}" height="{height}" fill="none" stroke="#999"/>',
             f'<text x="{left}" y="{top-6}" font-size="13" font-family="sans-serif">{title}</text>']
    for frac in (0, 0.5, 1):
        v = lo + (hi - lo) * frac
        parts.append(f'<text x="{left-6}" y="{py(v)+4:.1f}" font-size="11" text-anchor="end" '
                     f'font-family="sans-serif">{v:.2f}</text>')
    return parts, px, py


def write_svg(path, svg, x_labels, y):
    """Adds the x labels [(x pixel, text)] at height y, closes `svg` (a list of parts started with
    <svg ...>) and writes it to `path`."""
    for x, text in x_labels:
        svg.append(f'<text x="{x:.1f}" y="{y}" font-size="11" text-anchor="middle" '
                   f'font-family="sans-serif">{text}</text>')
    svg.append("</svg>")
    with open(path, "w") as out:
        out.write("\n".join(svg))
