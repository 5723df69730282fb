"""The command registry: the subcommands of ``mineburial``, each declared once as a
:class:`Command` by the part of the package it belongs to (issue 36 item 5).

The command line (:mod:`mineburial.cli`) names no system: it registers the generic commands
(``run``, ``example``) and imports the light modules of :data:`COMMAND_MODULES`, each of which
registers its system's commands: the mine's (``drop``, ``map``, ``compare``, ``sensitivity``,
``validate``, ``calibrate``: :mod:`mineburial.systems.mine.commands`) and the restraining
system's (``restrain``: :mod:`mineburial.systems.restraint.commands`). A command module
imports nothing heavy at its top: its ``run`` imports what the command needs when it runs, so
``mineburial --help`` stays fast (:mod:`mineburial.cli`'s docstring). Adding a command is one
:func:`register` call in such a module; adding a system's commands, one module named in
:data:`COMMAND_MODULES`.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
from collections.abc import Callable

__all__ = ["COMMAND_MODULES", "COMMANDS", "Command", "load", "register", "unregister"]

#: the modules that register the systems' commands, imported by :func:`load` in this order
COMMAND_MODULES = ("mineburial.systems.mine.commands", "mineburial.systems.restraint.commands")


@dataclasses.dataclass(frozen=True)
class Command:
    """One subcommand of ``mineburial``."""

    #: the subcommand's name on the command line
    name: str
    #: one line for ``mineburial --help``
    help: str
    #: ``add_arguments(parser)``: declares the command's arguments on its subparser
    add_arguments: Callable[[argparse.ArgumentParser], None]
    #: ``run(args) -> int``: runs the command (imports its own modules), returns the exit status
    run: Callable[[argparse.Namespace], int]
    #: whether an interrupted command keeps its finished work and resumes it when rerun with the
    #: same ``-o`` (the interrupt's one line says so)
    resumable: bool = False


#: the registered commands, in the order ``mineburial --help`` lists them
COMMANDS: dict[str, Command] = {}


def register(command: Command) -> Command:
    """Add ``command`` (a name registered twice is a programming error)."""
    if command.name in COMMANDS and COMMANDS[command.name] != command:
        raise ValueError(f"a command {command.name!r} is registered already")
    COMMANDS[command.name] = command
    return command


def unregister(name: str) -> None:
    """Remove the command ``name`` (tests that register their own)."""
    COMMANDS.pop(name, None)


def load() -> dict[str, Command]:
    """Import :data:`COMMAND_MODULES` (each registers its commands) and return the registry."""
    for module in COMMAND_MODULES:
        importlib.import_module(module)
    return COMMANDS
