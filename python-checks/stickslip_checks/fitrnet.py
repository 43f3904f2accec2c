"""MATLAB `fitrnet` networks (a `RegressionNeuralNetwork` saved in a .mat file) as ONNX
files our reader takes (issue 23; the entry point is import_fitrnet).

MATLAB stores the object as MCOS opaque data, a format MathWorks does not document; the
pip package mat-io (`matio.load_from_mat`) reads it into the object's properties. What
a fitrnet network computes (MATLAB's `predict`), read off those properties:

    z_0 = (x - Mu) ./ Sigma          standardised inputs (StandardizeData true; else x)
    z_k = f(W_k z_{k-1} + b_k)       k = 1 .. L-1, hidden layers, f the activation
    y   = W_L z_{L-1} + b_L          the linear output layer

with x the predictors in the order of DataSummary.PredictorNames, W_k
NeuralNetworkImpl.LayerWeights{k} as [out, in], b_k LayerBiases{k} as [out, 1], and
the response transform the identity. Everything that would change this is checked and
refused with a message that names it: categorical predictors, another response
transform or output activation, more than one output, hidden activations that are not
all one of tanh, relu, sigmoid (our law has one activation; "none", linear hidden
layers, is refused too: our reader wants an activation between dense layers),
inconsistent shapes, a non-finite number.

The ONNX graph (float64, opset 17, IR 8) is what `torch.onnx.export` writes for the
same network: Sub/Div for the standardisation, then Gemm (transB = 1, W as [out, in])
and one activation node per hidden layer. ONNX carries no units, roles or training
ranges, so they go into metadata_props as our reader expects them
(`stickslip.features`, `stickslip.target`, `stickslip.variant`; see
docs/command-line.md). The feature roles come from the predictor names (`ROLES`) or
from `--feature NAME:ROLE:UNIT:MIN:MAX` overrides; the ranges from the stored training
inputs (PrivX, min and max per column) unless an override gives them.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

# Predictor names (compared without case) whose role and unit need no flag.
ROLES = {
    "fn": ("normal_force", "N"),
    "f_n": ("normal_force", "N"),
    "normal_force": ("normal_force", "N"),
    "vs": ("sliding_velocity", "m/s"),
    "v": ("sliding_velocity", "m/s"),
    "v_s": ("sliding_velocity", "m/s"),
    "sliding_velocity": ("sliding_velocity", "m/s"),
}
FEATURE_ROLES = ("sliding_velocity", "normal_force", "other")
# fitrnet's hidden activations that our reader (stickslip_formats::onnx) takes, and the
# ONNX operator of each.
ACTIVATIONS = {"tanh": "Tanh", "relu": "Relu", "sigmoid": "Sigmoid"}
IDENTITY_TRANSFORM = "classreg.learning.transform.identity"
CLASSES = ("RegressionNeuralNetwork", "CompactRegressionNeuralNetwork")
OPSET, IR_VERSION = 17, 8


class FitrnetError(ValueError):
    """The .mat file holds no network this converter can write faithfully; the message
    names what."""


@dataclass(frozen=True)
class Feature:
    """One input column as our metadata describes it (stickslip.features)."""

    name: str
    unit: str
    role: str
    min: float
    max: float

    def as_json(self) -> dict:
        return {"name": self.name, "unit": self.unit, "role": self.role,
                "min": self.min, "max": self.max}


def parse_feature(text: str) -> Feature:
    """`NAME:ROLE:UNIT:MIN:MAX`, as `stickslip import-network --feature` reads it (UNIT
    may be empty); ValueError naming the field at fault."""
    parts = text.split(":")
    if len(parts) != 5:
        raise ValueError(f"'{text}': expected NAME:ROLE:UNIT:MIN:MAX (5 fields separated by "
                         f"':', UNIT may be empty), got {len(parts)} field(s)")
    name, role, unit, low, high = parts
    if not name:
        raise ValueError(f"'{text}': NAME is empty")
    if role not in FEATURE_ROLES:
        raise ValueError(f"'{text}': role '{role}' is not one of {', '.join(FEATURE_ROLES)}")
    bounds = []
    for what, field in (("MIN", low), ("MAX", high)):
        try:
            value = float(field)
        except ValueError:
            value = float("nan")
        if not np.isfinite(value):
            raise ValueError(f"'{text}': {what} '{field}' is not a finite number")
        bounds.append(value)
    return Feature(name, unit, role, bounds[0], bounds[1])


@dataclass(frozen=True)
class Fitrnet:
    """A checked fitrnet network: predict(x) is MATLAB's predict (module docstring)."""

    source: str
    predictors: tuple[str, ...]
    response: str
    mu: np.ndarray  # (n,), zeros when the inputs are not standardised
    sigma: np.ndarray  # (n,), ones when the inputs are not standardised
    standardised: bool
    weights: tuple[np.ndarray, ...]  # W_k as [out, in]
    biases: tuple[np.ndarray, ...]  # b_k as [out]
    activation: str  # a key of ACTIVATIONS
    low: np.ndarray | None  # (n,) training range per predictor, None if not stored
    high: np.ndarray | None
    response_range: tuple[float, float] | None

    def predict(self, x: np.ndarray) -> np.ndarray:
        """The response at the rows of x ([samples, predictors]), in float64."""
        z = ((np.asarray(x, float) - self.mu) / self.sigma).T
        f = {"tanh": np.tanh, "relu": lambda a: np.maximum(a, 0.0),
             "sigmoid": lambda a: 1.0 / (1.0 + np.exp(-a))}[self.activation]
        for k, (w, b) in enumerate(zip(self.weights, self.biases)):
            z = w @ z + b[:, None]
            if k < len(self.weights) - 1:
                z = f(z)
        return z[0]

    def features(self, overrides: list[Feature] = ()) -> list[Feature]:
        """Our description of each predictor, in column order: an override of the same
        name, else the role and unit its name implies (ROLES) and the stored training
        range. Refuses an override that names no predictor, a name with no known role
        and no override, and a missing range."""
        by_name = {f.name: f for f in overrides}
        unknown = [name for name in by_name if name not in self.predictors]
        if unknown:
            raise FitrnetError(f"{self.source}: --feature names {', '.join(unknown)}, which "
                               f"is not a predictor; the predictors are "
                               f"{', '.join(self.predictors)}")
        result = []
        for k, name in enumerate(self.predictors):
            if name in by_name:
                result.append(by_name[name])
                continue
            if name.lower() not in ROLES:
                raise FitrnetError(
                    f"{self.source}: predictor '{name}' has no known role (names known: "
                    f"{', '.join(sorted(ROLES))}); give it as --feature "
                    f"{name}:ROLE:UNIT:MIN:MAX with ROLE one of {', '.join(FEATURE_ROLES)}")
            if self.low is None:
                raise FitrnetError(
                    f"{self.source}: the training inputs (PrivX) are not stored (a compact "
                    f"model?), so the training range of '{name}' is unknown; give it as "
                    f"--feature {name}:ROLE:UNIT:MIN:MAX")
            role, unit = ROLES[name.lower()]
            result.append(Feature(name, unit, role, float(self.low[k]), float(self.high[k])))
        return result


# ----------------------------------------------------------------------------- reading


def _text(value) -> str:
    """A MATLAB char array as mat-io returns it (ndarray of one str) as str."""
    return str(np.asarray(value).ravel()[0]) if np.asarray(value).size else ""


def _texts(value) -> list[str]:
    """A cell array or string array of char arrays as a list of str."""
    return [_text(v) for v in np.asarray(value, dtype=object).ravel()]


def _transform_name(handle) -> str:
    """The function name of a MATLAB function handle as mat-io returns it (nested
    structured arrays whose `function_handle` struct has a `function` field); '' if
    none is found."""
    stack = [handle]
    while stack:
        item = stack.pop()
        if isinstance(item, np.ndarray) and item.dtype.names:
            if "function" in item.dtype.names:
                return _text(item.ravel()[0]["function"])
            stack.extend(item.ravel()[0][n] for n in item.dtype.names)
        elif isinstance(item, np.ndarray) and item.dtype == object:
            stack.extend(item.ravel())
    return ""


def _matrix(value, what: str, source: str) -> np.ndarray:
    a = np.asarray(value)
    if a.dtype.kind not in "fiu":
        raise FitrnetError(f"{source}: {what} is not numeric (dtype {a.dtype})")
    a = a.astype(np.float64)
    if not np.all(np.isfinite(a)):
        raise FitrnetError(f"{source}: {what} holds a non-finite number")
    return a


def from_properties(properties: dict, classname: str, source: str) -> Fitrnet:
    """The network described by a fitrnet object's properties (what mat-io reads);
    FitrnetError naming the first thing it cannot convert faithfully."""
    if classname not in CLASSES:
        raise FitrnetError(f"{source}: the object is a {classname}, not a "
                           f"{' or '.join(CLASSES)} (fitrnet)")
    try:
        return _network(properties, source)
    except (KeyError, IndexError, TypeError, AttributeError) as error:
        # The properties read here are those of MATLAB R2022a's objects; another release
        # may name or shape them otherwise.
        raise FitrnetError(f"{source}: the {classname} does not have the properties this "
                           f"converter reads (MATLAB R2022a's): {error!r}") from error


def _network(p: dict, source: str) -> Fitrnet:
    summary = np.asarray(p["DataSummary"]).ravel()[0]
    predictors = tuple(_texts(summary["PredictorNames"]))
    response = _text(summary["ResponseName"])
    if np.asarray(summary["CategoricalPredictors"]).size:
        raise FitrnetError(f"{source}: categorical predictors are not supported "
                           f"(CategoricalPredictors = "
                           f"{np.asarray(summary['CategoricalPredictors']).ravel().tolist()})")
    transform = _transform_name(p["PrivResponseTransform"])
    if transform != IDENTITY_TRANSFORM:
        raise FitrnetError(f"{source}: response transform '{transform}' is not supported "
                           f"(only {IDENTITY_TRANSFORM}: the output is the response)")
    output = _text(p["OutputLayerActivation"])
    if output != "none":
        raise FitrnetError(f"{source}: output layer activation '{output}' is not supported "
                           "(only 'none', a linear output)")
    impl = p["NeuralNetworkImpl"].properties
    outputs = int(np.asarray(impl["NumOutputs"]).ravel()[0])
    if outputs != 1:
        raise FitrnetError(f"{source}: {outputs} outputs; only one (the friction force) is "
                           "supported")
    if np.asarray(impl["OutputTransformation"]).size:
        raise FitrnetError(f"{source}: an output transformation is set "
                           "(NeuralNetworkImpl.OutputTransformation); not supported")
    weights = tuple(_matrix(w, f"LayerWeights{{{k + 1}}}", source)
                    for k, w in enumerate(np.asarray(impl["LayerWeights"], object).ravel()))
    biases = tuple(_matrix(b, f"LayerBiases{{{k + 1}}}", source).ravel()
                   for k, b in enumerate(np.asarray(impl["LayerBiases"], object).ravel()))
    if "ExpandedActivations" in p:  # one per layer, the output's ('linear') last
        hidden = _texts(p["ExpandedActivations"])[:-1]
    else:  # one for all hidden layers, or one per hidden layer
        hidden = _texts(p["Activations"])
        hidden = hidden * (len(weights) - 1) if len(hidden) == 1 else hidden
    activation = _activation(hidden, source)
    n = len(predictors)
    _check_shapes(weights, biases, n, source)
    standardised = bool(np.asarray(p["StandardizeData"]).ravel()[0])
    if standardised:
        mu = _matrix(p["Mu"], "Mu", source).ravel()
        sigma = _matrix(p["Sigma"], "Sigma", source).ravel()
        if mu.shape != (n,) or sigma.shape != (n,):
            raise FitrnetError(f"{source}: Mu {mu.shape} and Sigma {sigma.shape} do not have "
                               f"one value per predictor ({n})")
        if np.any(sigma <= 0.0):
            raise FitrnetError(f"{source}: Sigma {sigma.tolist()} is not positive")
    else:
        mu, sigma = np.zeros(n), np.ones(n)
    low = high = None
    response_range = None
    x = np.asarray(p.get("PrivX", np.empty((0, 0))))
    if x.ndim == 2 and x.shape[0] > 0:
        if x.shape[1] != n:
            raise FitrnetError(f"{source}: the training inputs PrivX have {x.shape[1]} "
                               f"columns, not one per predictor ({n})")
        x = _matrix(x, "PrivX", source)
        low, high = x.min(axis=0), x.max(axis=0)
        y = np.asarray(p.get("PrivY", np.empty(0)), float)
        if y.size:
            response_range = (float(y.min()), float(y.max()))
    return Fitrnet(source, predictors, response, mu, sigma, standardised, weights, biases,
                   activation, low, high, response_range)


def _activation(hidden: list[str], source: str) -> str:
    if not hidden:
        raise FitrnetError(f"{source}: the network has no hidden layer")
    kinds = sorted(set(hidden))
    if len(kinds) != 1:
        raise FitrnetError(f"{source}: hidden layers with different activations "
                           f"({', '.join(hidden)}); our law has one activation")
    if kinds[0] not in ACTIVATIONS:
        raise FitrnetError(f"{source}: hidden activation '{kinds[0]}' is not supported "
                           f"(supported: {', '.join(ACTIVATIONS)}; 'none' would put two "
                           "dense layers in a row, which our reader refuses)")
    return kinds[0]


def _check_shapes(weights, biases, n: int, source: str) -> None:
    if len(weights) != len(biases) or len(weights) < 2:
        raise FitrnetError(f"{source}: {len(weights)} weight and {len(biases)} bias arrays; "
                           "expected as many of each, at least two layers")
    width = n
    for k, (w, b) in enumerate(zip(weights, biases)):
        if w.ndim != 2 or w.shape[1] != width or b.shape != (w.shape[0],):
            raise FitrnetError(f"{source}: layer {k + 1} has weights {w.shape} and biases "
                               f"{b.shape}; expected (m, {width}) and (m,)")
        width = w.shape[0]
    if width != 1:
        raise FitrnetError(f"{source}: the last layer has {width} outputs, not 1")


def load_mat(path: str | Path) -> dict:
    """The variables of the .mat file `path` as mat-io reads them (MCOS objects with
    their `classname` and `properties`)."""
    import warnings

    with warnings.catch_warnings():
        # mat-io 1.0.2 sets pandas' future.infer_string option on import, which pandas 3
        # (where it is already the default) deprecates with a warning; nothing changes.
        warnings.simplefilter("ignore", DeprecationWarning)
        from matio import load_from_mat
    try:
        return load_from_mat(str(path))
    except OSError:
        raise
    except Exception as error:  # mat-io's own errors (MatReadError, ...) have no common base
        raise FitrnetError(f"{path}: not a MAT-file mat-io can read: {error}") from error


def read_fitrnet(path: str | Path, variable: str | None = None) -> Fitrnet:
    """The fitrnet network in the .mat file `path`: the variable of that name, or the
    only fitrnet object in the file."""
    source = str(path)
    contents = load_mat(source)
    candidates = {name: value for name, value in contents.items()
                  if getattr(value, "classname", None) in CLASSES}
    if variable is not None:
        if variable not in contents:
            raise FitrnetError(f"{source}: no variable '{variable}' (variables: "
                               f"{', '.join(contents) or 'none'})")
        value = contents[variable]
    elif len(candidates) == 1:
        value = next(iter(candidates.values()))
    else:
        raise FitrnetError(f"{source}: {len(candidates)} fitrnet objects "
                           f"({', '.join(candidates) or 'none'}) among the variables "
                           f"{', '.join(contents) or '(none)'}; name one with --variable")
    classname = getattr(value, "classname", type(value).__name__)
    return from_properties(value.properties if hasattr(value, "properties") else {},
                           classname, source)


# ----------------------------------------------------------------------------- ONNX


def to_onnx(network: Fitrnet, features: list[Feature], variant: str = "plain",
            target: dict | None = None):
    """The network as an onnx.ModelProto (float64, module docstring), described by
    `features` (one per predictor, in order), `target` (default: the response name in N
    with the stored response range) and `variant`."""
    import onnx
    from onnx import TensorProto, helper, numpy_helper

    if [f.name for f in features] != list(network.predictors):
        raise FitrnetError(f"{network.source}: features {[f.name for f in features]} are not "
                           f"the predictors {list(network.predictors)} in order")
    inits, nodes = [], []
    current = "input"
    if network.standardised:
        inits += [numpy_helper.from_array(network.mu, "Mu"),
                  numpy_helper.from_array(network.sigma, "Sigma")]
        nodes += [helper.make_node("Sub", ["input", "Mu"], ["centred"], name="/Sub"),
                  helper.make_node("Div", ["centred", "Sigma"], ["z0"], name="/Div")]
        current = "z0"
    last = len(network.weights) - 1
    for k, (w, b) in enumerate(zip(network.weights, network.biases)):
        inits += [numpy_helper.from_array(w, f"LayerWeights{k + 1}"),
                  numpy_helper.from_array(b, f"LayerBiases{k + 1}")]
        out = network.response if k == last else f"dense{k + 1}"
        nodes.append(helper.make_node(
            "Gemm", [current, f"LayerWeights{k + 1}", f"LayerBiases{k + 1}"], [out],
            name=f"/layer{k + 1}/Gemm", alpha=1.0, beta=1.0, transB=1))
        current = out
        if k < last:
            current = f"a{k + 1}"
            nodes.append(helper.make_node(ACTIVATIONS[network.activation], [out], [current],
                                          name=f"/layer{k + 1}/{network.activation}"))
    graph = helper.make_graph(
        nodes, "fitrnet",
        [helper.make_tensor_value_info("input", TensorProto.DOUBLE,
                                       ["batch", len(network.predictors)])],
        [helper.make_tensor_value_info(network.response, TensorProto.DOUBLE, ["batch", 1])],
        inits,
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", OPSET)],
                              producer_name="stickslip_checks.fitrnet", producer_version="1")
    model.ir_version = IR_VERSION
    model.doc_string = f"MATLAB fitrnet network converted from {Path(network.source).name}"
    if target is None:
        low, high = network.response_range or (0.0, 0.0)
        target = {"name": network.response, "unit": "N", "min": low, "max": high}
    helper.set_model_props(model, {
        "stickslip.features": json.dumps([f.as_json() for f in features]),
        "stickslip.target": json.dumps(target),
        "stickslip.variant": variant,
    })
    onnx.checker.check_model(model)
    return model
