"""Grammatical evolution, knowing nothing of floors: the BNF grammar read and compiled, genomes
mapped and decoded into populations, breeding operators, the evaluation cache, the evolution loop
and the problem (a build's spec, grammar and fitness module) that ties them together.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.engine._bnf import Grammar, parse_bnf, read_bnf
    from mazegen.runtime.engine._breeding import breed, make_children
    from mazegen.runtime.engine._cache import EvaluationCache, genome_hashes
    from mazegen.runtime.engine._compiled_grammar import CompiledGrammar, compile_grammar
    from mazegen.runtime.engine._evolution import (
        EVALUATION_CHUNK,
        GenerationStats,
        RunResult,
        RunState,
        evolve,
        generation_stats,
    )
    from mazegen.runtime.engine._mapping import PopulationMap, map_genome, map_population, phenotype
    from mazegen.runtime.engine._operators import mutate, mutation_draws, random_codons, random_genes, ranking
    from mazegen.runtime.engine._placement import PLACEMENT_GENES, SX, SY, THETA, Ranges, X, Y
    from mazegen.runtime.engine._population import Population, decode
    from mazegen.runtime.engine._problem import (
        REJECTED,
        Evaluation,
        Problem,
        Workspace,
        compiled_bnf,
        load_fitness,
        read_build_spec,
    )

__all__ = [
    "EVALUATION_CHUNK",
    "PLACEMENT_GENES",
    "REJECTED",
    "SX",
    "SY",
    "THETA",
    "CompiledGrammar",
    "Evaluation",
    "EvaluationCache",
    "GenerationStats",
    "Grammar",
    "Population",
    "PopulationMap",
    "Problem",
    "Ranges",
    "RunResult",
    "RunState",
    "Workspace",
    "X",
    "Y",
    "breed",
    "compile_grammar",
    "compiled_bnf",
    "decode",
    "evolve",
    "generation_stats",
    "genome_hashes",
    "load_fitness",
    "make_children",
    "map_genome",
    "map_population",
    "mutate",
    "mutation_draws",
    "parse_bnf",
    "phenotype",
    "random_codons",
    "random_genes",
    "ranking",
    "read_bnf",
    "read_build_spec",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_bnf": ["Grammar", "parse_bnf", "read_bnf"],
        "_breeding": ["breed", "make_children"],
        "_cache": ["EvaluationCache", "genome_hashes"],
        "_compiled_grammar": ["compile_grammar", "CompiledGrammar"],
        "_evolution": [
            "EVALUATION_CHUNK",
            "evolve",
            "generation_stats",
            "GenerationStats",
            "RunResult",
            "RunState",
        ],
        "_mapping": ["map_genome", "map_population", "phenotype", "PopulationMap"],
        "_operators": ["mutate", "mutation_draws", "random_codons", "random_genes", "ranking"],
        "_placement": ["PLACEMENT_GENES", "Ranges", "SX", "SY", "THETA", "X", "Y"],
        "_population": ["decode", "Population"],
        "_problem": [
            "compiled_bnf",
            "Evaluation",
            "load_fitness",
            "Problem",
            "read_build_spec",
            "REJECTED",
            "Workspace",
        ],
    },
)
