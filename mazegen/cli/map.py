"""``mazegen map GRAMMAR.bnf|SPEC.maze CODON...``: map genomes through a BNF grammar, or a spec's."""

from __future__ import annotations

import json
import re
from pathlib import Path

import click

from mazegen.cli.bounds import BoundedOption, setting, within
from mazegen.cli.errors import reports_errors
from mazegen.errors import MazeError
from mazegen.fileio import read_text
from mazegen.spec import CODON_MAX, Evolution
from mazegen.text import printable

_SEPARATOR = re.compile(r"[\s,]+")


def _genomes(path: Path) -> list[tuple[int, list[int]]]:
    genomes = []
    for number, line in enumerate(read_text(path, "genomes").splitlines(), start=1):
        text = line.strip().strip("[]")
        if not text:
            continue
        try:
            genome = [int(token) for token in _SEPARATOR.split(text) if token]
        except ValueError:
            raise MazeError(
                "a genome is integers separated by spaces or commas", filename=str(path), line=number, col=1
            ) from None
        if any(not 0 <= codon <= CODON_MAX for codon in genome):
            raise MazeError(f"codons must be from 0 to {CODON_MAX}", filename=str(path), line=number, col=1)
        genomes.append((number, genome))
    return genomes


@click.command("map")
@click.argument("grammar", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.argument("codons", nargs=-1, type=within(0, CODON_MAX, what="codon"))
@click.option(
    "--genomes",
    type=click.Path(exists=True, dir_okay=False, path_type=Path),
    help="File with one genome per line (codons separated by spaces or commas).",
)
@click.option(
    "--wraps",
    type=setting("wraps"),
    cls=BoundedOption,
    help="Extra passes over the genome.  [default: the spec's, else 0]",
)
@click.option(
    "--consume",
    type=click.Choice(["eager", "lazy"]),
    help="eager: one-alternative rules use a codon (PonyGE2); lazy: they do not.  "
    "[default: the spec's, else eager]",
)
@click.option("--json", "as_json", is_flag=True, help="One JSON object per genome.")
@reports_errors
def map_command(
    grammar: Path,
    codons: tuple[int, ...],
    genomes: Path | None,
    wraps: int | None,
    consume: str | None,
    as_json: bool,
) -> None:
    """Print the phenotype of each genome and the codons it used, or `invalid`.

    GRAMMAR is a BNF file, or a spec (.maze) whose grammar is built on the fly.
    """
    from mazegen.runtime.engine import map_genome, parse_bnf, read_bnf

    settings = Evolution()  # a bare grammar maps with the defaults
    if grammar.suffix == ".maze":
        from mazegen.dsl.loader import load_spec
        from mazegen.generator.build import grammar_text

        spec = load_spec(grammar)
        parsed = parse_bnf(grammar_text(spec), filename=f"{grammar} (its grammar)")
        settings = spec.evolution
    else:
        parsed = read_bnf(grammar)
    wraps = settings.wraps if wraps is None else wraps
    consume = settings.consume if consume is None else consume
    if genomes is not None:
        batch = [genome for _, genome in _genomes(genomes)]
    elif codons:
        batch = [list(codons)]
    else:
        raise MazeError("give codons after the grammar, or --genomes FILE")
    for genome in batch:
        if not genome:
            raise MazeError("a genome needs at least one codon")
        result = map_genome(parsed, genome, wraps=wraps, consume=consume)
        if as_json:
            click.echo(
                json.dumps(
                    {"phenotype": result.phenotype, "valid": result.valid, "used_codons": result.used_codons}
                )
            )
        elif result.valid:
            click.echo(f"{printable(result.phenotype or '')}\t{result.used_codons} codons")
        else:
            click.echo(f"invalid\t{result.used_codons} codons")
