"""POST /curves: evaluate a cubic Bezier curve and measure its length with a guaranteed error bound."""
from _common import check, client

r = client.curves([[0, 0], [1, 2], [3, 2], [4, 0]], evaluate=[0, 0.5, 1], length={"tolerance": 1e-6}).json
mid = r["evaluate"][1]
# B(1/2) = (P0 + 3 P1 + 3 P2 + P3) / 8
check(abs(mid[0] - 2.0) < 1e-12 and abs(mid[1] - 1.5) < 1e-12, f"B(0.5) = {mid}")
check(r["length"]["error_bound"] <= 1e-6 and 4 < r["length"]["length"] < 6.5, f"length {r['length']['length']:.9f}")
