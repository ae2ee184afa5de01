"""Grammatical evolution, knowing nothing of floors: the BNF grammar read and compiled, genomes
mapped and decoded into populations, breeding operators, the evaluation cache, the evolution loop
and the problem (a build's spec, grammar and fitness module) that ties them together.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.engine.bnf import Grammar, parse_bnf, read_bnf
    from mazegen.runtime.engine.breeding import breed
    from mazegen.runtime.engine.cache import EvaluationCache, genome_hashes
    from mazegen.runtime.engine.compiled_grammar import CompiledGrammar, compile_grammar
    from mazegen.runtime.engine.evolution import GenerationStats, RunResult, evolve
    from mazegen.runtime.engine.mapping import PopulationMap, map_genome, map_population, phenotype
    from mazegen.runtime.engine.population import Population, Ranges, decode
    from mazegen.runtime.engine.problem import Evaluation, Problem, Workspace

__all__ = [
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
    "Workspace",
    "breed",
    "compile_grammar",
    "decode",
    "evolve",
    "genome_hashes",
    "map_genome",
    "map_population",
    "parse_bnf",
    "phenotype",
    "read_bnf",
]

__getattr__ = lazy_names(
    __name__,
    {
        "bnf": ["Grammar", "parse_bnf", "read_bnf"],
        "cache": ["EvaluationCache", "genome_hashes"],
        "compiled_grammar": ["CompiledGrammar", "compile_grammar"],
        "breeding": ["breed"],
        "evolution": ["GenerationStats", "RunResult", "evolve"],
        "mapping": ["PopulationMap", "map_genome", "map_population", "phenotype"],
        "population": ["Population", "Ranges", "decode"],
        "problem": ["Evaluation", "Problem", "Workspace"],
    },
)
