"""Status codes that a run returns: the vocabulary every system of the integration core shares, and
the registry of each system's own names (see docs/design.md "integration core" and "Status codes").

Kernels never raise: each run ends with one of these codes, which the Python side records per drop or
case (CF ``flag_values``/``flag_meanings``) and turns into explanatory messages. The shared codes
(issue 18): 0 the system's normal end, which the system names (the mine ``at_rest``, the multibody
systems ``stopped``), 1 the time limit, 3 a numerical failure, 4 invalid inputs (nothing run); 2 and
5 and up are a system's own (2 is the mine's ``left_domain``, older than this vocabulary).

Each system contributes its names to the registry (issue 36 item 5): one :class:`Vocabulary` (its
codes in order, their names and descriptions, the codes whose results enter its statistics) handed
to :func:`register` by the module that declares the system's codes (the mine's:
:mod:`mineburial.kernels.mine.status`; the restraint's: :mod:`mineburial.systems.restraint.ensemble`, from the
multibody core's names). The layers that write or print statuses (the output variables' flag
attributes, statistics, printed summaries) read a system's names from its vocabulary,
:func:`vocabulary`; the kernels compare the codes as module-level integer constants (numba globals,
compile-time constants), which stay plain ints in the system's module.

This module imports nothing, so that the variable registry and the command line read it without numba.
"""

# --- shared by every system of the integration core ----------------------------------------------------
#: the system's normal end (named by the system)
END = 0
#: the time limit was reached before the system's end
TIME_LIMIT = 1
#: a non-finite state or rate, a step-size underflow or the step budget spent
NUMERICAL_FAILURE = 3
#: the inputs were invalid; nothing was run
INVALID_INPUT = 4

#: the names of the shared codes every system uses as they are (the normal end ``END`` is named by
#: each system)
SHARED_NAMES = {
    TIME_LIMIT: "time_limit",
    NUMERICAL_FAILURE: "numerical_failure",
    INVALID_INPUT: "invalid_input",
}


class Vocabulary:
    """The status codes of one system: ``names`` and ``descriptions`` map each code the system
    returns to its name (a CF ``flag_meanings`` word) and a sentence; ``in_statistics`` are the
    codes whose results enter the system's statistics. The codes are written in increasing order
    (``codes``: the CF ``flag_values``)."""

    __slots__ = ("system", "codes", "names", "descriptions", "in_statistics")

    def __init__(self, system: str, names, descriptions, in_statistics=()):
        names, descriptions = dict(names), dict(descriptions)
        codes = tuple(sorted(names))
        problems = []
        if set(descriptions) != set(names):
            problems.append(f"descriptions of codes {sorted(descriptions)} != names of codes {sorted(names)}")
        for code in codes:
            if not isinstance(code, int) or isinstance(code, bool) or not 0 <= code <= 127:
                problems.append(f"code {code!r} is not an integer in 0..127 (an int8 flag value)")
        for code in (END, *SHARED_NAMES):
            if code not in names:
                problems.append(f"the shared code {code} is missing")
        for code, shared in SHARED_NAMES.items():
            if code in names and names[code] != shared:
                problems.append(f"the shared code {code} is named {names[code]!r}, not {shared!r}")
        words = list(names.values())
        for word in words:
            if not isinstance(word, str) or not word.isidentifier() or words.count(word) > 1:
                problems.append(f"name {word!r} is not a unique single word (a CF flag meaning)")
        if not set(in_statistics) <= set(names):
            problems.append(f"in_statistics {tuple(in_statistics)} names codes outside {codes}")
        if problems:
            raise ValueError(f"status vocabulary of {system!r}: " + "; ".join(problems))
        self.system = system
        self.codes = codes
        self.names = {code: names[code] for code in codes}
        self.descriptions = {code: descriptions[code] for code in codes}
        self.in_statistics = tuple(in_statistics)

    @property
    def flag_meanings(self) -> str:
        """The CF ``flag_meanings`` attribute: the names in code order, space-separated."""
        return " ".join(self.names.values())

    def name(self, code) -> str:
        """The name of ``code`` (an int or a numpy integer)."""
        return self.names[int(code)]

    def __eq__(self, other):
        return isinstance(other, Vocabulary) and all(
            getattr(self, k) == getattr(other, k) for k in self.__slots__
        )

    def __hash__(self):
        return hash((self.system, self.codes))

    def __repr__(self):
        return f"Vocabulary({self.system!r}, {self.names!r}, in_statistics={self.in_statistics!r})"


#: system name -> its vocabulary, in the order the systems registered
VOCABULARIES: dict = {}


def register(vocab: Vocabulary) -> Vocabulary:
    """Add a system's vocabulary (:class:`Vocabulary`); registering the same one again does
    nothing, another under the same system name is refused (ValueError)."""
    known = VOCABULARIES.get(vocab.system)
    if known is not None and known != vocab:
        raise ValueError(f"a different status vocabulary of {vocab.system!r} is registered already")
    VOCABULARIES.setdefault(vocab.system, vocab)
    return VOCABULARIES[vocab.system]


def vocabulary(system: str) -> Vocabulary:
    """The registered vocabulary of ``system`` (KeyError naming the registered ones)."""
    try:
        return VOCABULARIES[system]
    except KeyError:
        raise KeyError(
            f"no status vocabulary of system {system!r}; registered: {', '.join(VOCABULARIES) or 'none'} "
            "(a system's status module registers it when imported)"
        ) from None
