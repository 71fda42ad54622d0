"""Reads a file Kilohertz wrote for ParaView with VTK's own readers and prints, as JSON, what VTK
sees: point and cell counts, coordinates, cell types and every array's values (doubles printed so
that they read back exactly). A .pvd collection is parsed with VTK's XML parser and each of its
datasets read as above.

Usage: vtk_readback.py FILE. Exits non-zero, with VTK's message, if VTK reports an error or reads
nothing. test_tools_vtk_readback runs it; Debian's python3-vtk9 provides `vtk`.
"""
import json
import math
import os
import sys

import vtk


class ErrorCatcher:
    """Collects the errors VTK reports (its readers print them and carry on)."""

    def __init__(self):
        self.messages = []

    def __call__(self, caller, event, data=None):
        self.messages.append(str(data) if data is not None else event)


def watched(algorithm, catcher):
    algorithm.AddObserver("ErrorEvent", catcher)
    algorithm.AddObserver("WarningEvent", catcher)
    return algorithm


def number(x):
    """JSON has no NaN or infinity: those come as the strings "nan", "inf" and "-inf"."""
    return x if math.isfinite(x) else str(x)


def array_values(array):
    components = array.GetNumberOfComponents()
    return {
        "type": array.GetDataTypeAsString(),
        "components": components,
        "values": [
            number(array.GetComponent(t, c))
            for t in range(array.GetNumberOfTuples())
            for c in range(components)
        ],
    }


def arrays(data):
    return {
        data.GetArrayName(i): array_values(data.GetAbstractArray(i))
        for i in range(data.GetNumberOfArrays())
    }


def describe(data):
    result = {
        "class": data.GetClassName(),
        "points": data.GetNumberOfPoints(),
        "cells": data.GetNumberOfCells(),
        "point_data": arrays(data.GetPointData()),
        "cell_data": arrays(data.GetCellData()),
    }
    if data.IsA("vtkImageData"):
        result["dimensions"] = list(data.GetDimensions())
        result["origin"] = list(data.GetOrigin())
        result["spacing"] = list(data.GetSpacing())
        return result
    result["coordinates"] = [
        number(data.GetPoint(p)[k]) for p in range(data.GetNumberOfPoints()) for k in range(3)
    ]
    result["cell_types"] = [data.GetCellType(c) for c in range(data.GetNumberOfCells())]
    result["cell_points"] = [
        [data.GetCell(c).GetPointId(k) for k in range(data.GetCell(c).GetNumberOfPoints())]
        for c in range(data.GetNumberOfCells())
    ]
    return result


READERS = {
    ".vtk": vtk.vtkUnstructuredGridReader,
    ".vtu": vtk.vtkXMLUnstructuredGridReader,
    ".vtp": vtk.vtkXMLPolyDataReader,
    ".vti": vtk.vtkXMLImageDataReader,
}


def read_dataset(path, catcher):
    extension = os.path.splitext(path)[1]
    if extension not in READERS:
        raise SystemExit(f"{path}: no VTK reader for {extension}")
    reader = watched(READERS[extension](), catcher)
    reader.SetFileName(path)
    if extension == ".vtk":
        reader.ReadAllScalarsOn()
        reader.ReadAllVectorsOn()
        reader.ReadAllFieldsOn()
    reader.Update()
    return describe(reader.GetOutput())


def read_collection(path, catcher):
    parser = watched(vtk.vtkXMLDataParser(), catcher)
    parser.SetFileName(path)
    if not parser.Parse():
        raise SystemExit(f"{path}: VTK's XML parser rejects it")
    root = parser.GetRootElement()
    if root.GetName() != "VTKFile" or root.GetAttribute("type") != "Collection":
        raise SystemExit(f"{path}: not a VTKFile of type Collection")
    collection = root.FindNestedElementWithName("Collection")
    directory = os.path.dirname(path)
    datasets = []
    for i in range(collection.GetNumberOfNestedElements()):
        entry = collection.GetNestedElement(i)
        datasets.append(
            {
                "timestep": float(entry.GetAttribute("timestep")),
                "part": entry.GetAttribute("part"),
                "name": entry.GetAttribute("name"),
                "file": entry.GetAttribute("file"),
                "data": read_dataset(os.path.join(directory, entry.GetAttribute("file")), catcher),
            }
        )
    return {"class": "collection", "datasets": datasets}


def main():
    path = sys.argv[1]
    catcher = ErrorCatcher()
    if path.endswith(".pvd"):
        result = read_collection(path, catcher)
    else:
        result = read_dataset(path, catcher)
    if catcher.messages:
        raise SystemExit(f"{path}: VTK reports: " + " | ".join(catcher.messages))
    json.dump(result, sys.stdout)


if __name__ == "__main__":
    main()
