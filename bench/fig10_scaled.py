#!/usr/bin/env python3
"""Writes the Figure 10 scenario (scenarios/fig10.toml) scaled by k (bench/README.md, issue 13):
every position, radius, sink box, noise scale and the iteration count times k. With --pad-to NX NY NZ
the scaled features sit in the corner of a block of that size (the padding test).

usage: fig10_scaled.py K [--pad-to NX NY NZ] > scenario.toml
"""
import pathlib
import re
import sys


def main():
    k = int(sys.argv[1])
    text = (pathlib.Path(__file__).resolve().parent.parent / "scenarios" / "fig10.toml").read_text()
    times_k = lambda m: m.group(1) + re.sub(r"\d+(\.\d+)?", lambda n: str(float(n[0]) * k if n[1] else int(n[0]) * k),
                                            m.group(2))
    text = re.sub(r"^((?:size|center|radius|at|box|iterations) = )(.*)$", times_k, text, flags=re.M)
    text = re.sub(r"(\bscale = )([\d.]+)", times_k, text)
    text = text.replace('name = "fig10"', f'name = "fig10_k{k}"')
    if "--pad-to" in sys.argv:
        i = sys.argv.index("--pad-to")
        text = re.sub(r"^size = .*$", "size = [%s]" % ", ".join(sys.argv[i + 1:i + 4]), text, flags=re.M)
    print(text, end="")


main()
