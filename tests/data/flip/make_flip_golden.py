#!/usr/bin/env python3
"""Golden LDR-FLIP values for tests/unit/image/flip_test.cpp (FlipGolden.*).

An independent implementation of LDR-FLIP, written from the formulas of Andersson et al.,
"FLIP: A Difference Evaluator for Alternating Images" (HPG 2020) and the implementation choices
that docs/metrics.md lists (clamp-to-edge borders, one CSF radius for all channels, features on
the unfiltered achromatic channel, clamping of inputs, filtered colours and errors). It shares no
code with server/metrics/: plain 2-D convolutions instead of separable passes, numpy's matrix
inverse instead of a written-out one, the published sRGB matrix. Agreement with the C++ is
therefore evidence that both follow the formulas, which the C++ tests alone (whose expectations
came from the library's own filters) could not give.

Run by hand, not in CI (it needs numpy: apt-get install -y python3-numpy):

    /usr/bin/python3 tests/data/flip/make_flip_golden.py

and paste the printed values into flip_test.cpp. The images are integer codes / 256, exact in
float32 and double, built by the same formulas in the test.
"""
import math

import numpy as np

# --- Colour -------------------------------------------------------------------------------
# IEC 61966-2-1 (sRGB) linear RGB -> CIE XYZ, D65.
RGB_TO_XYZ = np.array([[0.4124564, 0.3575761, 0.1804375],
                       [0.2126729, 0.7151522, 0.0721750],
                       [0.0193339, 0.1191920, 0.9503041]])
XYZ_TO_RGB = np.linalg.inv(RGB_TO_XYZ)
WHITE = RGB_TO_XYZ @ np.ones(3)  # the reference white is the XYZ of RGB (1, 1, 1)


def srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def to_xyz(rgb):  # (..., 3) linear RGB -> (..., 3) XYZ
    return rgb @ RGB_TO_XYZ.T


def xyz_to_ycxcz(xyz):
    x, y, z = (xyz[..., i] / WHITE[i] for i in range(3))
    return np.stack([116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)], axis=-1)


def ycxcz_to_xyz(ycc):
    y = (ycc[..., 0] + 16.0) / 116.0
    x = ycc[..., 1] / 500.0 + y
    z = y - ycc[..., 2] / 200.0
    return np.stack([x * WHITE[0], y * WHITE[1], z * WHITE[2]], axis=-1)


def lab_f(t):
    delta = 6.0 / 29.0
    return np.where(t > delta ** 3, np.cbrt(t), t / (3.0 * delta * delta) + 4.0 / 29.0)


def xyz_to_lab(xyz):
    fx, fy, fz = (lab_f(xyz[..., i] / WHITE[i]) for i in range(3))
    return np.stack([116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)], axis=-1)


def hunt(lab):  # the paper's Hunt adjustment: chroma scaled by 0.01 L*
    return np.stack([lab[..., 0], 0.01 * lab[..., 0] * lab[..., 1],
                     0.01 * lab[..., 0] * lab[..., 2]], axis=-1)


def hyab(a, b):
    return np.abs(a[..., 0] - b[..., 0]) + np.hypot(a[..., 1] - b[..., 1], a[..., 2] - b[..., 2])


# --- Filters --------------------------------------------------------------------------------
def convolve2d(plane, kernel):
    """Convolution with clamp-to-edge borders; kernel of odd size, centred."""
    r = kernel.shape[0] // 2
    padded = np.pad(plane, r, mode="edge")
    h, w = plane.shape
    out = np.zeros_like(plane)
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            # out(x, y) += k(dx, dy) * in(x - dx, y - dy)
            out += kernel[dy + r, dx + r] * padded[r - dy:r - dy + h, r - dx:r - dx + w]
    return out


# Paper, sec. 3.2: (a1, b1, a2, b2) of the achromatic, red-green and blue-yellow CSFs.
CSF = [(1.0, 0.0047, 0.0, 1e-5), (1.0, 0.0053, 0.0, 1e-5), (34.1, 0.04, 13.5, 0.025)]


def csf_kernel(params, ppd):
    a1, b1, a2, b2 = params
    # 3 standard deviations of the widest Gaussian (b = 0.04), for every channel.
    r = math.ceil(3.0 * math.sqrt(0.04 / (2.0 * math.pi ** 2)) * ppd)
    d = np.arange(-r, r + 1) / ppd  # degrees
    r2 = d[None, :] ** 2 + d[:, None] ** 2
    s = (a1 * math.sqrt(math.pi / b1) * np.exp(-math.pi ** 2 * r2 / b1) +
         a2 * math.sqrt(math.pi / b2) * np.exp(-math.pi ** 2 * r2 / b2))
    return s / s.sum()


def feature_kernels(ppd):
    """2-D kernels (x derivative, y derivative) of the edge and point detectors."""
    sigma = 0.5 * 0.082 * ppd
    r = math.ceil(3.0 * sigma)
    x = np.arange(-r, r + 1, dtype=float)
    g = np.exp(-x * x / (2.0 * sigma * sigma))

    def signed_unit(k):  # positive taps sum to 1, negative taps to -1
        pos, neg = k > 0, k < 0
        out = np.zeros_like(k)
        out[pos] = k[pos] / k[pos].sum()
        out[neg] = -k[neg] / k[neg].sum()
        return out

    first = signed_unit(-x / sigma ** 2 * g)
    second = signed_unit((x * x / sigma ** 2 - 1.0) / sigma ** 2 * g)
    across = g / g.sum()
    return [(np.outer(across, k), np.outer(k, across)) for k in (first, second)]


def features(achromatic, ppd):
    out = []
    for kx, ky in feature_kernels(ppd):
        out.append(np.hypot(convolve2d(achromatic, kx), convolve2d(achromatic, ky)))
    return out  # [edges, points]


# --- FLIP -----------------------------------------------------------------------------------
def flip(reference, test, ppd):
    """Per-pixel LDR-FLIP of two (h, w, 3) sRGB images."""
    p_c, p_t, q_c, q_f = 0.4, 0.95, 0.7, 0.5
    green = hunt(xyz_to_lab(to_xyz(np.array([0.0, 1.0, 0.0]))))
    blue = hunt(xyz_to_lab(to_xyz(np.array([0.0, 0.0, 1.0]))))
    cmax = hyab(green, blue) ** q_c

    def prepare(image):
        ycc = xyz_to_ycxcz(to_xyz(srgb_to_linear(np.clip(image, 0.0, 1.0))))
        filtered = np.stack([convolve2d(ycc[..., i], csf_kernel(CSF[i], ppd)) for i in range(3)],
                            axis=-1)
        rgb = np.clip(ycxcz_to_xyz(filtered) @ XYZ_TO_RGB.T, 0.0, 1.0)
        lab = hunt(xyz_to_lab(to_xyz(rgb)))
        return lab, features((ycc[..., 0] + 16.0) / 116.0, ppd)

    lab_r, (edge_r, point_r) = prepare(reference)
    lab_t, (edge_t, point_t) = prepare(test)
    d = hyab(lab_r, lab_t) ** q_c
    color = np.where(d < p_c * cmax, p_t / (p_c * cmax) * d,
                     p_t + (d - p_c * cmax) / (cmax - p_c * cmax) * (1.0 - p_t))
    color = np.clip(color, 0.0, 1.0)
    feature = (np.maximum(np.abs(edge_r - edge_t), np.abs(point_r - point_t)) /
               math.sqrt(2.0)) ** q_f
    return np.clip(color ** (1.0 - feature), 0.0, 1.0)


# --- The test's image pairs (same formulas as flip_test.cpp) --------------------------------
def image(w, h, code):
    return np.array([[[code(x, y, c) / 256.0 for c in range(3)] for x in range(w)]
                     for y in range(h)])


def square_pair():  # a gradient, and the same with a saturated orange square
    ref = image(24, 18, lambda x, y, c: (16 + 8 * x, 16 + 10 * y, 128)[c])
    in_square = lambda x, y: 9 <= x <= 14 and 6 <= y <= 11
    test = image(24, 18, lambda x, y, c: (240, 64, 32)[c] if in_square(x, y) else
                 (16 + 8 * x, 16 + 10 * y, 128)[c])
    return ref, test


def bars_pair():  # reddish/greenish bars against yellowish/bluish bars, two pixels wide
    ref = image(16, 12, lambda x, y, c: ((160, 96, 96) if (x // 2) % 2 == 0 else (96, 160, 96))[c])
    test = image(16, 12, lambda x, y, c: ((160, 160, 96) if (x // 2) % 2 == 0 else
                                          (96, 96, 160))[c])
    return ref, test


def noise_pair():  # integer-hash noise and a perturbed copy, with out-of-range pixels
    ref = image(20, 16, lambda x, y, c: (x * 37 + y * 101 + c * 59) % 256)
    test = image(20, 16, lambda x, y, c: (x * 37 + y * 101 + c * 59 + 11 * ((x + 2 * y) % 5)) % 256)
    ref[4, 3] = (1.25, -0.25, 0.5)  # row 4, column 3
    test[9, 15] = (-0.5, 1.5, 2.0)
    return ref, test


CASES = [("square", square_pair, 67.0, [(11, 8), (9, 6), (4, 4)]),
         ("bars", bars_pair, 20.0, [(0, 0), (5, 7), (15, 11)]),
         ("noise", noise_pair, 67.0, [(3, 4), (15, 9), (10, 10)])]

if __name__ == "__main__":
    for name, make, ppd, pixels in CASES:
        ref, test = make()
        errors = flip(ref, test, ppd)
        values = ", ".join(f"{{{x}, {y}, {errors[y, x]:.9f}}}" for x, y in pixels)
        print(f"{name}: ppd {ppd}, mean {errors.mean():.9f}, pixels {values}")
