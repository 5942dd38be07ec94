"""The compiled error-of-fit kernel (numba): residuals of paper eq. (9) and their Jacobian.

This is the one implementation of the EOF that hapticsim runs; :mod:`hapticsim.geometry.eof` is
its public face. (The vectorised numpy kernel it replaced survives only as the test oracle,
``tests/geometry/eof_oracle.py``; the two agree to 1e-10 relative.)

Per contact and body, with p the tapered body-frame point and m the data normal in the body frame:

- untaper (eq. 2): ``x_s = x / f_x``, ``f_x = max(1 + t_x z / a3, MIN_TAPER_FACTOR)``, same for y;
- the inside-outside function in the log domain (SPEC §1), as the oracle does, so that the
  exponents of box-like shapes (2 / eps up to 20) cannot overflow:
  ``l_u = log(|x_s| / a1 + TINY)``, ``A_u = (2/eps2) l_u``, ``log g = logaddexp(A_u, A_v)``,
  ``L1 = (eps2/eps1) log g``, ``L2 = (2/eps1) l_w``, ``log F = logaddexp(L1, L2)``. Each
  ``logaddexp`` also gives the *shares* of its two terms (``phi_u = |u|^(2/eps2) / g``,
  ``psi_G = g^(eps2/eps1) / F``, ...), and with them the gradient of F
  (``h_u = phi_u psi_G``, ``h_w = psi_W``) comes for free: five logarithms and three
  exponentials per contact in all;
- ``D1 = |1 - s| rho`` with ``s = F^(-eps1/2)`` and rho the length of the untapered point, or
  (``tapered``) of the ray's offset mapped back through the taper;
- the model normal ``n = (h_u / x, h_v / y, h_w / z - (t_x/a3) h_u / f_x - (t_y/a3) h_v / f_y)``
  (eqs. 3-4) and ``D2 = |m - n/|n||^2 = 2 (1 - m.n/|n|)``; the residual is
  ``|D1| + lambda sigma D2`` with ``sigma = mean(a)``.

**Jacobian.** Analytic, by reverse-mode differentiation of the steps above written out per
contact (:func:`contact_residual_gradient`): the derivatives of the residual with respect to the
body point, the body normal and a, eps, taper; then the chain rule through
``p = R^T (x_world - x0)`` gives the centre (``-R dr/dp``) and the rotation vector
(``dR/dtheta_k = [J_l(theta) e_k]_x R`` with J_l the left Jacobian of SO(3), so
``dr/dtheta = J_l^T (g x d + g_m x m)``, g and g_m the world-frame gradients). A Jacobian costs
about two residual evaluations instead of the 13 of forward differences; the fitter still
*counts* 13 (SPEC §3), so budgets keep their meaning.

**Speed.** The loop over contacts is straight-line code (selects, no branches or calls), so LLVM
vectorises it: the logarithm and exponential are written here in plain arithmetic (Cody-Waite
reduction and short series; relative error below 1e-15, :func:`exp_` and :func:`log_`) instead of
calling libm, which LLVM cannot vectorise. Contacts are stored as (3, n) rows so the vector
loads are contiguous. Everything is compiled with ``cache=True``: a fresh process loads the
machine code from numba's cache instead of compiling it again (seconds).

The Jacobian's loop reads 6 rows and writes 14 (the residual and 13 Jacobian rows), and LLVM
must check at run time that none of them overlap: more pairs than its loop vectoriser allows by
default (128), so it stayed scalar (42 microseconds for 150 contacts on an AMD Zen 5 core, 5.5
residual evaluations). :data:`VECTORIZER_OPTIONS` raises that limit to 256 when this module is
imported, before any of hapticsim's kernels is compiled; the loop then runs vectorised, in 7.6
microseconds. The option only lets LLVM guard more vector loops with run-time overlap checks
(of this process's numba code): every lane still does the scalar loop's IEEE operations in the
same order, so the results are the same bit for bit (the refactor digest does not move).

**Shared with fitting.** The passes of one contact (:func:`shape_forward`, :func:`normal_forward`
and their reverses), the frames (:func:`body_frame`, :func:`jacobian_frame`, :func:`to_body`,
:func:`rotate_to_body`) and :func:`world_column` are public: nML's residuals
(:mod:`hapticsim.fitting._ml_compiled`) inline them, and the solvers reach the residuals through
:mod:`hapticsim.fitting._problem_compiled`.
"""

from __future__ import annotations

import math

import llvmlite.binding as llvm
import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

from hapticsim._jit_cache import ensure_fresh
from hapticsim.constants import MIN_TAPER_FACTOR
from hapticsim.geometry.layout import I_A, I_CENTER, I_EPS, I_ROTVEC, I_TAPER, N_PARAMS

ensure_fresh()  # before any cached kernel of hapticsim is loaded (they all import this module)

#: LLVM options set once per process before the kernels compile (module docstring, "Speed").
VECTORIZER_OPTIONS: tuple[str, ...] = ("-vectorize-memory-check-threshold=256",)
#: LLVM major versions the option is set in: it exists in all of them (22 is numba 0.68's, the
#: newest checked). LLVM exits the process on an option it does not know, so a newer LLVM goes
#: without it (a scalar Jacobian, the same results) until it is checked there and the bound
#: raised.
VECTORIZER_LLVM: tuple[int, int] = (11, 22)
if VECTORIZER_LLVM[0] <= llvm.llvm_version_info[0] <= VECTORIZER_LLVM[1]:
    for _option in VECTORIZER_OPTIONS:
        llvm.set_option("hapticsim", _option)

#: Floor added to |x / a| before its log (as the oracle): finite logs on the body planes.
TINY = 1e-150

#: Compilation options of everything here: cached machine code, no GIL, IEEE division (inf/nan
#: instead of exceptions, which would stop vectorisation).
JIT = {"cache": True, "nogil": True, "error_model": "numpy"}
INLINE = {"forceinline": True, **JIT}


def unpack(sq) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # noqa: ANN001 - a Superquadric
    """``(shape (7,), rot (3, 3), center (3,))`` of a superquadric, for the compiled helpers of
    single solids: shape = (a1, a2, a3, eps1, eps2, tx, ty) [m, 1, 1]."""
    shape = np.concatenate([sq.a, sq.eps, sq.taper])
    return shape, np.ascontiguousarray(sq.rotation), np.ascontiguousarray(sq.center)


@njit(**INLINE)
def shape_fields(shape: np.ndarray) -> tuple[float, float, float, float, float, float, float]:
    """``(a1, a2, a3, eps1, eps2, tx, ty)`` of an :func:`unpack` shape (7,) as scalars."""
    return shape[0], shape[1], shape[2], shape[3], shape[4], shape[5], shape[6]


# ---------------------------------------------------------------------------- elementary
@intrinsic
def _f64_bits(typingctx, x):  # type: ignore[no-untyped-def]
    """The IEEE bits of a float64 as an int64 (a register bitcast, vectorisable)."""

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.bitcast(args[0], ir.IntType(64))

    return types.int64(types.float64), codegen


@intrinsic
def _bits_f64(typingctx, x):  # type: ignore[no-untyped-def]
    """The float64 with the given IEEE bits (int64)."""

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(types.int64), codegen


# Cody-Waite split of log(2): LN2_HI has trailing zero bits, so k * LN2_HI is exact.
_LN2_HI = 6.93147180369123816490e-01
_LN2_LO = 1.90821492927058770002e-10
_INV_LN2 = 1.4426950408889634
_SQRT2 = 1.4142135623730951
_MANTISSA = 0x000FFFFFFFFFFFFF
_EXP_ONE = 0x3FF0000000000000


@njit(**INLINE)
def exp_(x: float) -> float:
    """``e^x`` in plain arithmetic (relative error < 1e-15; 0 below -708, inf above 709.7).

    ``x = k log 2 + r`` with ``|r| <= log(2) / 2``, ``e^r`` by its Taylor series to ``r^13``
    (truncation < 5e-18), then scaled by ``2^k`` through the exponent bits.
    """
    xc = min(max(x, -708.0), 709.7)
    k = math.floor(xc * _INV_LN2 + 0.5)
    r = (xc - k * _LN2_HI) - k * _LN2_LO
    p = 1.0 / 6227020800.0
    p = p * r + 1.0 / 479001600.0
    p = p * r + 1.0 / 39916800.0
    p = p * r + 1.0 / 3628800.0
    p = p * r + 1.0 / 362880.0
    p = p * r + 1.0 / 40320.0
    p = p * r + 1.0 / 5040.0
    p = p * r + 1.0 / 720.0
    p = p * r + 1.0 / 120.0
    p = p * r + 1.0 / 24.0
    p = p * r + 1.0 / 6.0
    p = p * r + 0.5
    p = p * r + 1.0
    p = p * r + 1.0
    y = p * _bits_f64((np.int64(k) + 1023) << 52)
    y = 0.0 if x < -708.0 else y
    return math.inf if x > 709.7 else y


@njit(**INLINE)
def log_(x: float) -> float:
    """Natural log of a positive normal float in plain arithmetic (relative error < 1e-15).

    ``x = m 2^e`` with ``m`` in [sqrt(1/2), sqrt(2)), ``log m = 2 atanh(f)``,
    ``f = (m - 1) / (m + 1)``, ``|f| <= 0.172``, by its series to ``f^21`` (truncation < 1e-18).
    """
    bits = _f64_bits(x)
    e = (bits >> 52) - 1023
    m = _bits_f64((bits & _MANTISSA) | _EXP_ONE)
    big = m > _SQRT2
    m = m * 0.5 if big else m
    e = e + 1 if big else e
    f = (m - 1.0) / (m + 1.0)
    f2 = f * f
    p = 1.0 / 21.0
    p = p * f2 + 1.0 / 19.0
    p = p * f2 + 1.0 / 17.0
    p = p * f2 + 1.0 / 15.0
    p = p * f2 + 1.0 / 13.0
    p = p * f2 + 1.0 / 11.0
    p = p * f2 + 1.0 / 9.0
    p = p * f2 + 1.0 / 7.0
    p = p * f2 + 1.0 / 5.0
    p = p * f2 + 1.0 / 3.0
    p = p * f2 + 1.0
    ef = float(e)
    return ef * _LN2_HI + (ef * _LN2_LO + 2.0 * f * p)


@njit(**INLINE)
def _logaddexp_shares(x: float, y: float) -> tuple[float, float, float]:
    """``(log(e^x + e^y), e^x / (e^x + e^y), e^y / (e^x + e^y))`` without overflow."""
    d = exp_(-abs(x - y))
    inv = 1.0 / (1.0 + d)
    big, small = inv, d * inv
    first = x >= y
    return max(x, y) + log_(1.0 + d), (big if first else small), (small if first else big)


@njit(**INLINE)
def _sign(x: float) -> float:
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


# ---------------------------------------------------------------------------- one point
@njit(**INLINE)
def untapered(
    px: float, py: float, pz: float, a3: float, tx: float, ty: float
) -> tuple[float, float, float, float]:
    """``(x_s, y_s, f_x, f_y)``: a tapered body point's untapered x, y and its taper factors
    ``max(1 + t z / a3, MIN_TAPER_FACTOR)`` (paper eq. 2)."""
    ia3 = 1.0 / a3
    fx = max(1.0 + tx * ia3 * pz, MIN_TAPER_FACTOR)
    fy = max(1.0 + ty * ia3 * pz, MIN_TAPER_FACTOR)
    return px / fx, py / fy, fx, fy


@njit(**INLINE)
def log_inside_outside(
    xs: float, ys: float, zs: float, a1: float, a2: float, a3: float, e1: float, e2: float
) -> tuple[float, float, float, float, float]:
    """The inside-outside function of an untapered body point in the log domain (SPEC §1).

    The one compiled implementation of F. Returns ``(log F, phi_u, phi_v, psi_G, psi_W)``:
    ``phi_u = |u|^(2/eps2) / g`` and ``phi_v`` (summing to 1), ``psi_G = g^(eps2/eps1) / F`` and
    ``psi_W = |w|^(2/eps1) / F`` (summing to 1), from which the gradient follows
    (``h_u = phi_u psi_G``, ``h_v = phi_v psi_G``, ``h_w = psi_W``).
    """
    lu = log_(abs(xs) * (1.0 / a1) + TINY)
    lv = log_(abs(ys) * (1.0 / a2) + TINY)
    lw = log_(abs(zs) * (1.0 / a3) + TINY)
    k2 = 2.0 / e2
    log_g, phu, phv = _logaddexp_shares(lu * k2, lv * k2)
    log_f, psg, psw = _logaddexp_shares(log_g * (e2 / e1), lw * (2.0 / e1))
    return log_f, phu, phv, psg, psw


# ---------------------------------------------------------------------------- one contact
@njit(**INLINE)
def contact_residual(
    px: float, py: float, pz: float, mx: float, my: float, mz: float,
    a1: float, a2: float, a3: float, e1: float, e2: float, tx: float, ty: float,
    wlam: float, with_normals: bool, tapered: bool,
) -> float:  # fmt: skip
    """Residual of one contact: body point p [m], body unit data normal m, ``wlam`` the normal
    term's weight ``2 lambda sigma`` [m]."""
    ia3 = 1.0 / a3
    ta, tb = tx * ia3, ty * ia3
    xs, ys, fx, fy = untapered(px, py, pz, a3, tx, ty)
    log_f, phu, phv, psg, psw = log_inside_outside(xs, ys, pz, a1, a2, a3, e1, e2)
    s = exp_(log_f * (-0.5 * e1))
    if tapered:
        b = pz * (1.0 + s)
        qx, qy = (b * ta + 1.0) * xs, (b * tb + 1.0) * ys
        rho = math.sqrt(qx * qx + qy * qy + pz * pz)
    else:
        rho = math.sqrt(xs * xs + ys * ys + pz * pz)
    d1 = abs(s - 1.0) * rho
    if not with_normals:
        return d1
    hu, hv = phu * psg, phv * psg
    nx = hu / px if px != 0.0 else 0.0
    ny = hv / py if py != 0.0 else 0.0
    nz = (psw / pz if pz != 0.0 else 0.0) - ta * hu / fx - tb * hv / fy
    length = math.sqrt(nx * nx + ny * ny + nz * nz) + 1e-300
    dot = (nx * mx + ny * my + nz * mz) / length
    return d1 + wlam * abs(1.0 - dot)


@njit(**INLINE)
def shape_forward(
    px: float, py: float, pz: float, a1: float, a2: float, a3: float, e1: float, e2: float,
    tx: float, ty: float,
) -> tuple:  # fmt: skip
    """The forward pass shared by the gradients: untaper, log F with its shares, and s.

    Returns the intermediates :func:`shape_backward` and :func:`normal_forward` need, in the
    order ``(ia1, ia2, ia3, ta, tb, cx, cy, fx, fy, xs, ys, qu, qv, qw, lu, lv, lw, k2, k1,
    ratio, log_g, phu, phv, log_f, psg, psw, s)``.
    """
    ia1, ia2, ia3 = 1.0 / a1, 1.0 / a2, 1.0 / a3
    ta, tb = tx * ia3, ty * ia3
    fxr, fyr = 1.0 + ta * pz, 1.0 + tb * pz
    cx, cy = fxr >= MIN_TAPER_FACTOR, fyr >= MIN_TAPER_FACTOR
    fx, fy = max(fxr, MIN_TAPER_FACTOR), max(fyr, MIN_TAPER_FACTOR)
    xs, ys = px / fx, py / fy
    qu, qv, qw = abs(xs) * ia1, abs(ys) * ia2, abs(pz) * ia3
    lu, lv, lw = log_(qu + TINY), log_(qv + TINY), log_(qw + TINY)
    k2, k1, ratio = 2.0 / e2, 2.0 / e1, e2 / e1
    au, av = lu * k2, lv * k2
    log_g, phu, phv = _logaddexp_shares(au, av)
    l1, l2 = log_g * ratio, lw * k1
    log_f, psg, psw = _logaddexp_shares(l1, l2)
    s = exp_(log_f * (-0.5 * e1))
    return (
        ia1, ia2, ia3, ta, tb, cx, cy, fx, fy, xs, ys, qu, qv, qw, lu, lv, lw, k2, k1, ratio,
        log_g, phu, phv, log_f, psg, psw, s,
    )  # fmt: skip


@njit(**INLINE)
def normal_forward(
    px: float, py: float, pz: float, ta: float, tb: float, fx: float, fy: float,
    phu: float, phv: float, psg: float, psw: float,
) -> tuple[float, float, float, float, float, float, float, float, float]:  # fmt: skip
    """The unnormalised model normal ``n = grad_p log G`` (module docstring) and its parts:
    ``(hu, hv, hw, nx, ny, nz0, qa, qb, nz)``."""
    hu, hv, hw = phu * psg, phv * psg, psw
    nx = hu / px if px != 0.0 else 0.0
    ny = hv / py if py != 0.0 else 0.0
    nz0 = hw / pz if pz != 0.0 else 0.0
    qa, qb = ta * hu / fx, tb * hv / fy
    nz = nz0 - qa - qb
    return hu, hv, hw, nx, ny, nz0, qa, qb, nz


@njit(**INLINE)
def normal_backward(
    g_nx: float, g_ny: float, g_nz: float, px: float, py: float, pz: float, ta: float,
    tb: float, fx: float, fy: float, phu: float, phv: float, psg: float, hu: float, hv: float,
    nx: float, ny: float, nz0: float, qa: float, qb: float,
) -> tuple:  # fmt: skip
    """Adjoints of :func:`normal_forward` from those of n: ``(g_ta, g_tb, g_fx, g_fy, g_px,
    g_py, g_pz, g_phu, g_phv, g_psg, g_psw)``."""
    # nz = nz0 - ta hu / fx - tb hv / fy
    g_ta = -g_nz * hu / fx
    g_tb = -g_nz * hv / fy
    g_hu = -g_nz * ta / fx
    g_hv = -g_nz * tb / fy
    g_fx = g_nz * qa / fx
    g_fy = g_nz * qb / fy
    # nx = hu / px, ny = hv / py, nz0 = hw / pz (0 on the planes)
    nzx, nzy, nzz = px != 0.0, py != 0.0, pz != 0.0
    g_hu += g_nx / px if nzx else 0.0
    g_px = -g_nx * nx / px if nzx else 0.0
    g_hv += g_ny / py if nzy else 0.0
    g_py = -g_ny * ny / py if nzy else 0.0
    g_hw = g_nz / pz if nzz else 0.0
    g_pz = -g_nz * nz0 / pz if nzz else 0.0
    g_phu, g_phv = g_hu * psg, g_hv * psg
    g_psg = g_hu * phu + g_hv * phv
    g_psw = g_hw
    return g_ta, g_tb, g_fx, g_fy, g_px, g_py, g_pz, g_phu, g_phv, g_psg, g_psw


@njit(**INLINE)
def shape_backward(
    g_s: float, g_phu: float, g_phv: float, g_psg: float, g_psw: float,
    g_xs: float, g_ys: float, g_pz: float, g_px: float, g_py: float, g_fx: float, g_fy: float,
    g_ta: float, g_tb: float, g_a1: float, g_a2: float, g_a3: float, g_e1: float, g_e2: float,
    fw: tuple, px: float, py: float, pz: float, tx: float, ty: float, e1: float, e2: float,
) -> tuple[float, float, float, float, float, float, float, float, float, float]:  # fmt: skip
    """Reverse pass of :func:`shape_forward` (`fw` its result): from the adjoints of s, the
    shares and the partial adjoints accumulated so far to ``dr/d(px, py, pz, a1, a2, a3, eps1,
    eps2, tx, ty)``."""
    (ia1, ia2, ia3, ta, tb, cx, cy, fx, fy, xs, ys, qu, qv, qw, lu, lv, lw, k2, k1, ratio,
     log_g, phu, phv, log_f, psg, psw, s) = fw  # fmt: skip
    # s = exp(-eps1 log F / 2)
    g_z = g_s * s
    g_e1 += -0.5 * log_f * g_z
    g_lf = -0.5 * e1 * g_z
    # (log F, psi_G, psi_W) = logaddexp(L1, L2)
    cross = (g_psg - g_psw) * psg * psw
    g_l1 = g_lf * psg + cross
    g_l2 = g_lf * psw - cross
    # L2 = k1 lw, L1 = ratio log g
    g_lw = g_l2 * k1
    g_e1 += -g_l2 * lw * k1 / e1
    g_lg = g_l1 * ratio
    g_ratio = g_l1 * log_g
    g_e2 += g_ratio / e1
    g_e1 += -g_ratio * ratio / e1
    # (log g, phi_u, phi_v) = logaddexp(A_u, A_v)
    cross = (g_phu - g_phv) * phu * phv
    g_au = g_lg * phu + cross
    g_av = g_lg * phv - cross
    # A_u = k2 lu
    g_lu, g_lv = g_au * k2, g_av * k2
    g_e2 += -(g_au * lu + g_av * lv) * k2 / e2
    # lu = log(|xs| / a1 + TINY), ...
    du, dv, dw = g_lu / (qu + TINY), g_lv / (qv + TINY), g_lw / (qw + TINY)
    g_xs += du * _sign(xs) * ia1
    g_a1 -= du * qu * ia1
    g_ys += dv * _sign(ys) * ia2
    g_a2 -= dv * qv * ia2
    g_pz += dw * _sign(pz) * ia3
    g_ia3 = dw * abs(pz)
    # xs = px / fx, ys = py / fy
    g_px += g_xs / fx
    g_fx -= g_xs * xs / fx
    g_py += g_ys / fy
    g_fy -= g_ys * ys / fy
    # fx = max(1 + ta pz, MIN)
    g_fx = g_fx if cx else 0.0
    g_fy = g_fy if cy else 0.0
    g_ta += g_fx * pz
    g_tb += g_fy * pz
    g_pz += g_fx * ta + g_fy * tb
    # ta = tx / a3, tb = ty / a3
    g_tx, g_ty = g_ta * ia3, g_tb * ia3
    g_ia3 += g_ta * tx + g_tb * ty
    g_a3 -= g_ia3 * ia3 * ia3
    return g_px, g_py, g_pz, g_a1, g_a2, g_a3, g_e1, g_e2, g_tx, g_ty


@njit(**INLINE)
def contact_residual_gradient(
    px: float, py: float, pz: float, mx: float, my: float, mz: float,
    a1: float, a2: float, a3: float, e1: float, e2: float, tx: float, ty: float,
    lam23: float, with_normals: bool, tapered: bool,
) -> tuple[float, ...]:  # fmt: skip
    """:func:`contact_residual` and its derivatives, by reverse-mode differentiation.

    Args:
        lam23: ``2 lambda / 3``; the normal term's weight is ``lam23 (a1 + a2 + a3)``.

    Returns:
        14 floats: the residual r, then dr/d(px, py, pz), dr/d(mx, my, mz),
        dr/d(a1, a2, a3), dr/d(eps1, eps2), dr/d(tx, ty). Where r has a kink (|D1| at the
        surface, a coordinate exactly 0) the derivative of the side with sign 0 is taken.
    """
    # ---- forward (as contact_residual, keeping the intermediates)
    fw = shape_forward(px, py, pz, a1, a2, a3, e1, e2, tx, ty)
    ta, tb, fx, fy, xs, ys = fw[3], fw[4], fw[7], fw[8], fw[9], fw[10]
    phu, phv, psg, psw, s = fw[21], fw[22], fw[24], fw[25], fw[26]
    b = pz * (1.0 + s)
    bx, by = b * ta + 1.0, b * tb + 1.0
    if tapered:
        qx, qy = bx * xs, by * ys
    else:
        qx, qy = xs, ys
    rho = math.sqrt(qx * qx + qy * qy + pz * pz)
    sm1 = s - 1.0
    d1 = abs(sm1) * rho

    # ---- reverse: adjoints (g_ = dr/d...) in the opposite order
    g_ta = g_tb = g_fx = g_fy = g_xs = g_ys = g_pz = g_px = g_py = 0.0
    g_a1 = g_a2 = g_a3 = 0.0
    g_phu = g_phv = g_psg = g_psw = 0.0
    g_mx = g_my = g_mz = 0.0
    r = d1
    if with_normals:
        hu, hv, hw, nx, ny, nz0, qa, qb, nz = normal_forward(
            px, py, pz, ta, tb, fx, fy, phu, phv, psg, psw
        )
        lraw = math.sqrt(nx * nx + ny * ny + nz * nz)
        length = lraw + 1e-300
        dot = (nx * mx + ny * my + nz * mz) / length
        d2 = abs(1.0 - dot)
        wlam = lam23 * (a1 + a2 + a3)
        r = d1 + wlam * d2
        g_a1 = g_a2 = g_a3 = lam23 * d2
        g_dot = -_sign(1.0 - dot) * wlam
        g_mn = g_dot / length
        g_len = -g_dot * dot / length
        g_mx, g_my, g_mz = g_mn * nx, g_mn * ny, g_mn * nz
        il = g_len / lraw if lraw > 0.0 else 0.0
        g_nx, g_ny, g_nz = g_mn * mx + il * nx, g_mn * my + il * ny, g_mn * mz + il * nz
        (g_ta, g_tb, g_fx, g_fy, g_px, g_py, g_pz, g_phu, g_phv, g_psg, g_psw) = normal_backward(
            g_nx, g_ny, g_nz, px, py, pz, ta, tb, fx, fy, phu, phv, psg, hu, hv, nx, ny, nz0,
            qa, qb,
        )  # fmt: skip
    # d1 = |s - 1| rho
    g_s = _sign(sm1) * rho
    g_rho = abs(sm1)
    ir_ = g_rho / rho if rho > 0.0 else 0.0
    g_qx, g_qy = ir_ * qx, ir_ * qy
    g_pz += ir_ * pz
    if tapered:
        # qx = bx xs, bx = 1 + ta b, b = pz (1 + s)
        g_xs += g_qx * bx
        g_ys += g_qy * by
        g_bx, g_by = g_qx * xs, g_qy * ys
        g_ta += g_bx * b
        g_tb += g_by * b
        g_b = g_bx * ta + g_by * tb
        g_pz += g_b * (1.0 + s)
        g_s += g_b * pz
    else:
        g_xs += g_qx
        g_ys += g_qy
    (g_px, g_py, g_pz, g_a1, g_a2, g_a3, g_e1, g_e2, g_tx, g_ty) = shape_backward(
        g_s, g_phu, g_phv, g_psg, g_psw, g_xs, g_ys, g_pz, g_px, g_py, g_fx, g_fy, g_ta, g_tb,
        g_a1, g_a2, g_a3, 0.0, 0.0, fw, px, py, pz, tx, ty, e1, e2,
    )  # fmt: skip
    return (
        r, g_px, g_py, g_pz, g_mx, g_my, g_mz, g_a1, g_a2, g_a3, g_e1, g_e2, g_tx, g_ty
    )  # fmt: skip


# ---------------------------------------------------------------------------- frames
@njit(**INLINE)
def body_frame(rot: np.ndarray, center: np.ndarray) -> tuple:
    """A pose as scalars: ``(c0, c1, c2, r00, r01, ..., r22)`` from R (3, 3) and x0 (3,)."""
    return (
        center[0], center[1], center[2], rot[0, 0], rot[0, 1], rot[0, 2], rot[1, 0], rot[1, 1],
        rot[1, 2], rot[2, 0], rot[2, 1], rot[2, 2],
    )  # fmt: skip


@njit(**INLINE)
def jacobian_frame(x: np.ndarray) -> tuple:
    """The pose of parameter vector `x` for a Jacobian: :func:`body_frame`, its rotation entries
    (``f[3:]``) and the left Jacobian of the rotation vector's map, as 9 scalars (row-major)."""
    rot = np.empty((3, 3))
    rotvec_matrix(x[I_ROTVEC], x[I_ROTVEC + 1], x[I_ROTVEC + 2], rot)
    jl = np.empty((3, 3))
    left_jacobian(x[I_ROTVEC], x[I_ROTVEC + 1], x[I_ROTVEC + 2], jl)
    f = body_frame(rot, x[I_CENTER : I_CENTER + 3])
    jm = (jl[0, 0], jl[0, 1], jl[0, 2], jl[1, 0], jl[1, 1], jl[1, 2], jl[2, 0], jl[2, 1],
          jl[2, 2])  # fmt: skip
    return f, f[3:], jm


@njit(**INLINE)
def to_body(x: float, y: float, z: float, f: tuple) -> tuple:
    """``(d0, d1, d2, bx, by, bz)``: the offset ``d = x - x0`` [world] and ``R^T d`` [body]."""
    c0, c1, c2, r00, r01, r02, r10, r11, r12, r20, r21, r22 = f
    d0, d1, d2 = x - c0, y - c1, z - c2
    return (
        d0, d1, d2, r00 * d0 + r10 * d1 + r20 * d2, r01 * d0 + r11 * d1 + r21 * d2,
        r02 * d0 + r12 * d1 + r22 * d2,
    )  # fmt: skip


@njit(**INLINE)
def rotate_to_body(x: float, y: float, z: float, f: tuple) -> tuple[float, float, float]:
    """``R^T v`` of a world-frame direction v."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = f[3:]
    return (
        r00 * x + r10 * y + r20 * z, r01 * x + r11 * y + r21 * z, r02 * x + r12 * y + r22 * z
    )  # fmt: skip


@njit(**JIT)
def vector_fields(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(a, eps, taper, center)`` of P parameter vectors (P, 13) as contiguous copies (loops:
    slices would compile the posed kernels for a second array layout, and slice copies cost
    more to compile)."""
    count = vectors.shape[0]
    a, eps, taper, center = (np.empty((count, 3)), np.empty((count, 2)), np.empty((count, 2)),
                             np.empty((count, 3)))  # fmt: skip
    for i in range(count):
        for k in range(3):
            a[i, k] = vectors[i, I_A + k]
            center[i, k] = vectors[i, I_CENTER + k]
        for k in range(2):
            eps[i, k] = vectors[i, I_EPS + k]
            taper[i, k] = vectors[i, I_TAPER + k]
    return a, eps, taper, center


@njit(**JIT)
def vector_poses(
    vectors: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(a, eps, taper, rot, center)`` of P parameter vectors (P, 13): the posed kernels'
    arguments, the rotation vectors turned into matrices (P, 3, 3) (:func:`vector_fields`)."""
    count = vectors.shape[0]
    rot = np.empty((count, 3, 3))
    for k in range(count):
        rotvec_matrix(vectors[k, I_ROTVEC], vectors[k, I_ROTVEC + 1], vectors[k, I_ROTVEC + 2],
                      rot[k])  # fmt: skip
    a, eps, taper, center = vector_fields(vectors)
    return a, eps, taper, rot, center


# ---------------------------------------------------------------------------- rotations
@njit(**JIT)
def rotvec_matrix(v0: float, v1: float, v2: float, out: np.ndarray) -> None:
    """Rodrigues' formula into `out` (3, 3), as ``rotations.rotvec_to_matrix``."""
    xx, yy, zz = v0 * v0, v1 * v1, v2 * v2
    t2 = xx + yy + zz
    theta = math.sqrt(t2)
    if theta < 1e-4:
        s = 1.0 - t2 / 6.0
        c = 0.5 - t2 / 24.0
    else:
        s = math.sin(theta) / theta
        c = (1.0 - math.cos(theta)) / (theta * theta)
    cxy, cxz, cyz = c * v0 * v1, c * v0 * v2, c * v1 * v2
    sx, sy, sz = s * v0, s * v1, s * v2
    out[0, 0] = 1.0 - c * (yy + zz)
    out[0, 1] = cxy - sz
    out[0, 2] = cxz + sy
    out[1, 0] = cxy + sz
    out[1, 1] = 1.0 - c * (xx + zz)
    out[1, 2] = cyz - sx
    out[2, 0] = cxz - sy
    out[2, 1] = cyz + sx
    out[2, 2] = 1.0 - c * (xx + yy)


@njit(**JIT)
def left_jacobian(v0: float, v1: float, v2: float, out: np.ndarray) -> None:
    """Left Jacobian of SO(3) at rotation vector v into `out` (3, 3).

    ``J_l = I + b [v]_x + c [v]_x^2`` with ``b = (1 - cos t) / t^2``, ``c = (t - sin t) / t^3``
    (Taylor limits below t = 1e-4): ``Exp(v + dv) ~ Exp(J_l dv) Exp(v)``.
    """
    t2 = v0 * v0 + v1 * v1 + v2 * v2
    t = math.sqrt(t2)
    if t < 1e-4:
        b = 0.5 - t2 / 24.0
        c = 1.0 / 6.0 - t2 / 120.0
    else:
        b = (1.0 - math.cos(t)) / t2
        c = (t - math.sin(t)) / (t2 * t)
    # [v]_x^2 = v v^T - t^2 I
    out[0, 0] = 1.0 + c * (v0 * v0 - t2)
    out[1, 1] = 1.0 + c * (v1 * v1 - t2)
    out[2, 2] = 1.0 + c * (v2 * v2 - t2)
    out[0, 1] = -b * v2 + c * v0 * v1
    out[1, 0] = b * v2 + c * v0 * v1
    out[0, 2] = b * v1 + c * v0 * v2
    out[2, 0] = -b * v1 + c * v0 * v2
    out[1, 2] = -b * v0 + c * v1 * v2
    out[2, 1] = b * v0 + c * v1 * v2


# ---------------------------------------------------------------------------- bodies
@njit(**JIT)
def residuals_posed(
    points: np.ndarray, normals: np.ndarray, with_normals: bool,
    a: np.ndarray, eps: np.ndarray, taper: np.ndarray, rot: np.ndarray, center: np.ndarray,
    lam: float, tapered: bool, out: np.ndarray, tally: np.ndarray,
) -> None:  # fmt: skip
    """Residuals (P, n) [m] into `out` for P bodies given with rotation matrices.

    Args:
        points: (3, n) float, contacts [m, world], one row per coordinate.
        normals: (3, n) float unit normals (anything when not `with_normals`).
        a: (P, 3); eps: (P, 2); taper: (P, 2); rot: (P, 3, 3); center: (P, 3).
        lam: lambda of the normal term; tapered: the distance mode (see the module).
        out: (P, n) float.
        tally: (1,) int64, incremented by the evaluations done (P; a Jacobian counts 13):
            the count the fitter's budget bookkeeping is checked against.
    """
    tally[0] += a.shape[0]
    n = points.shape[1]
    lam23 = 2.0 * lam / 3.0
    px_w, py_w, pz_w = points[0], points[1], points[2]
    nx_w, ny_w, nz_w = normals[0], normals[1], normals[2]
    for k in range(a.shape[0]):
        a1, a2, a3 = a[k, 0], a[k, 1], a[k, 2]
        e1, e2 = eps[k, 0], eps[k, 1]
        tx, ty = taper[k, 0], taper[k, 1]
        f = body_frame(rot[k], center[k])
        wlam = lam23 * (a1 + a2 + a3)
        row = out[k]
        for i in range(n):
            bx, by, bz = to_body(px_w[i], py_w[i], pz_w[i], f)[3:]
            mx = my = mz = 0.0
            if with_normals:
                mx, my, mz = rotate_to_body(nx_w[i], ny_w[i], nz_w[i], f)
            row[i] = contact_residual(
                bx, by, bz, mx, my, mz, a1, a2, a3, e1, e2, tx, ty, wlam, with_normals, tapered
            )


@njit(**JIT)
def residuals_vectors(
    points: np.ndarray, normals: np.ndarray, with_normals: bool, vectors: np.ndarray,
    lam: float, tapered: bool, out: np.ndarray, tally: np.ndarray,
) -> None:  # fmt: skip
    """Residuals (P, n) [m] into `out` for P parameter vectors (P, 13); see
    :func:`residuals_posed` for the other arguments."""
    a, eps, taper, rot, center = vector_poses(vectors)
    residuals_posed(
        points, normals, with_normals, a, eps, taper, rot, center, lam, tapered, out, tally,
    )  # fmt: skip


@njit(**INLINE)
def world_column(
    jac_t: np.ndarray, col: int, gpx: float, gpy: float, gpz: float, gmx: float, gmy: float,
    gmz: float, ga1: float, ga2: float, ga3: float, ge1: float, ge2: float, gtx: float,
    gty: float, rm: tuple, jm: tuple, d0: float, d1: float, d2: float, m0: float, m1: float,
    m2: float,
) -> None:  # fmt: skip
    """Column `col` of the transposed Jacobian (13, m) from one residual's body-frame gradient.

    ``rm``, ``jm``: the rotation and its left Jacobian, row-major 9-tuples; ``d = x - x0`` and
    m the world-frame offset and data normal. The chain rule of the module docstring:
    ``dr/dtheta = J_l^T (g x d + g_m x m)``, ``dr/dx0 = -g``, with ``g = R dr/dp``.
    """
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = rm
    j00, j01, j02, j10, j11, j12, j20, j21, j22 = jm
    i = col
    jac_t[I_A, i], jac_t[I_A + 1, i], jac_t[I_A + 2, i] = ga1, ga2, ga3
    jac_t[I_EPS, i], jac_t[I_EPS + 1, i] = ge1, ge2
    jac_t[I_TAPER, i], jac_t[I_TAPER + 1, i] = gtx, gty
    # World-frame gradients g = R dr/dp and g_m = R dr/dm.
    g0 = r00 * gpx + r01 * gpy + r02 * gpz
    g1 = r10 * gpx + r11 * gpy + r12 * gpz
    g2 = r20 * gpx + r21 * gpy + r22 * gpz
    h0 = r00 * gmx + r01 * gmy + r02 * gmz
    h1 = r10 * gmx + r11 * gmy + r12 * gmz
    h2 = r20 * gmx + r21 * gmy + r22 * gmz
    # dr/dtheta = J_l^T (g x d + g_m x m); dr/dx0 = -g.
    v0 = (g1 * d2 - g2 * d1) + (h1 * m2 - h2 * m1)
    v1 = (g2 * d0 - g0 * d2) + (h2 * m0 - h0 * m2)
    v2 = (g0 * d1 - g1 * d0) + (h0 * m1 - h1 * m0)
    jac_t[I_ROTVEC, i] = j00 * v0 + j10 * v1 + j20 * v2
    jac_t[I_ROTVEC + 1, i] = j01 * v0 + j11 * v1 + j21 * v2
    jac_t[I_ROTVEC + 2, i] = j02 * v0 + j12 * v1 + j22 * v2
    jac_t[I_CENTER, i], jac_t[I_CENTER + 1, i], jac_t[I_CENTER + 2, i] = -g0, -g1, -g2


@njit(**JIT)
def jacobian_vector(
    points: np.ndarray, normals: np.ndarray, with_normals: bool, x: np.ndarray,
    lam: float, tapered: bool, r_out: np.ndarray, jac_t: np.ndarray, tally: np.ndarray,
) -> None:  # fmt: skip
    """Residuals (n,) and the transposed Jacobian (13, n) of one parameter vector `x` (13,).

    Row k of `jac_t` holds dr_i / dx_k; the other arguments as :func:`residuals_posed`. It
    counts 13 evaluations in `tally` (what forward differences would cost, SPEC §3; the
    residuals at x come with it, as they do with forward differences).
    """
    tally[0] += N_PARAMS
    n = points.shape[1]
    f, rm, jm = jacobian_frame(x)
    a1, a2, a3 = x[I_A], x[I_A + 1], x[I_A + 2]
    e1, e2, tx, ty = x[I_EPS], x[I_EPS + 1], x[I_TAPER], x[I_TAPER + 1]
    lam23 = 2.0 * lam / 3.0
    px_w, py_w, pz_w = points[0], points[1], points[2]
    nx_w, ny_w, nz_w = normals[0], normals[1], normals[2]
    for i in range(n):
        d0, d1, d2, bx, by, bz = to_body(px_w[i], py_w[i], pz_w[i], f)
        m0 = m1 = m2 = mx = my = mz = 0.0
        if with_normals:
            m0, m1, m2 = nx_w[i], ny_w[i], nz_w[i]
            mx, my, mz = rotate_to_body(m0, m1, m2, f)
        (r, gpx, gpy, gpz, gmx, gmy, gmz, ga1, ga2, ga3, ge1, ge2, gtx, gty) = (
            contact_residual_gradient(
                bx, by, bz, mx, my, mz, a1, a2, a3, e1, e2, tx, ty, lam23, with_normals, tapered
            )
        )
        r_out[i] = r
        world_column(
            jac_t, i, gpx, gpy, gpz, gmx, gmy, gmz, ga1, ga2, ga3, ge1, ge2, gtx, gty, rm, jm,
            d0, d1, d2, m0, m1, m2,
        )  # fmt: skip
