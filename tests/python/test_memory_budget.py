"""A particle spacing the machine cannot hold is refused by fmi2ExitInitializationMode
with fmi2Error and a message naming dp, the particle count and the budget, before
anything is allocated; the instance can be reset and used. `memory_budget` sets the
budget."""

import resource
import time

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave


def start(path, name, **values):
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    start = {v.name: float(v.start) for v in md.modelVariables if v.start is not None
             and v.type == "Real"}
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    for k, v in values.items():
        fmu.setReal([vr[k]], [v])
    return fmu, vr, start


def test_a_spacing_of_1e_7_is_refused_without_allocating(fmus, capsys):
    fmu, vr, start0 = start(fmus["barrier"], "fine", particle_spacing=1e-7)
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t = time.perf_counter()
    with pytest.raises(FMICallException):
        fmu.exitInitializationMode()
    took = time.perf_counter() - t
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss0) / 1024
    out = capsys.readouterr().out
    assert took < 2.0, took
    assert grown_mb < 100, grown_mb
    for part in ("dp = 1e-7 m", "particles", "over the memory budget", "memory_budget"):
        assert part in out, out
    # the instance is not lost: reset, a spacing it can hold, and it steps
    fmu.reset()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setReal([vr["particle_spacing"]], [start0["particle_spacing"]])
    fmu.exitInitializationMode()
    fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=1e-3)
    assert fmu.getReal([vr["barrier.force.x"]])[0] > 0.0
    fmu.terminate()
    fmu.freeInstance()


def test_the_memory_budget_parameter_sets_the_budget(fmus, capsys):
    fmu, vr, start0 = start(fmus["barrier"], "budget", memory_budget=1e5)
    assert start0["memory_budget"] == 0.0
    with pytest.raises(FMICallException):
        fmu.exitInitializationMode()
    assert "over the memory budget of 97.7 KiB" in capsys.readouterr().out
    fmu.reset()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setReal([vr["memory_budget"]], [1e9])
    fmu.exitInitializationMode()
    fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=1e-3)
    fmu.terminate()
    fmu.freeInstance()
