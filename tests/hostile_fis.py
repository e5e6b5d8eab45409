"""A small Sugeno .fis with names chosen by the test: MATLAB's format quotes names, so it is
the importer that lets the most hostile text through (`Name='a */ int x = 5; /* b'`)."""
from __future__ import annotations


def sugeno_fis(system: str, inputs: list[tuple[str, str, str]],
               output: tuple[str, str, str]) -> str:
    """inputs: (name, low term, high term), each over [0, 1] with triangles peaking at 0 and 1;
    output: (name, term = 2, term = 8) over [0, 10].  Rule 1: every input low -> the first
    output term; rule 2: every input high -> the second (weighted average)."""
    n = len(inputs)
    text = [f"[System]\nName='{system}'\nType='sugeno'\nVersion=2.0\nNumInputs={n}\n"
            "NumOutputs=1\nNumRules=2\nAndMethod='min'\nOrMethod='max'\nImpMethod='prod'\n"
            "AggMethod='sum'\nDefuzzMethod='wtaver'\n"]
    for k, (name, lo, hi) in enumerate(inputs, start=1):
        text.append(f"[Input{k}]\nName='{name}'\nRange=[0 1]\nNumMFs=2\n"
                    f"MF1='{lo}':'trimf',[-1 0 1]\nMF2='{hi}':'trimf',[0 1 2]\n")
    name, small, big = output
    text.append(f"[Output1]\nName='{name}'\nRange=[0 10]\nNumMFs=2\n"
                f"MF1='{small}':'constant',[2]\nMF2='{big}':'constant',[8]\n")
    text.append("[Rules]\n" + " ".join(["1"] * n) + ", 1 (1) : 1\n"
                + " ".join(["2"] * n) + ", 2 (1) : 1\n")
    return "\n".join(text)
