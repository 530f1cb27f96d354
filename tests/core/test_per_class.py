"""Hot methods copied per subclass: the same behaviour, a code object of each class's own."""

from __future__ import annotations

from btnav.core.per_class import copy_hot_methods, original


class Base:
    def hot(self, x: int, *, k: int = 2) -> int:
        """Doubled, plus what a subclass adds."""
        return x * k + self.extra()

    def extra(self) -> int:
        return 0

    def __init_subclass__(cls, **kwargs: object) -> None:
        super().__init_subclass__(**kwargs)
        copy_hot_methods(cls, ("hot", "missing"))


class Child(Base):
    def extra(self) -> int:
        return 1


class Grandchild(Child):
    def hot(self, x: int, *, k: int = 2) -> int:
        return super().hot(x, k=k) + 100


class GreatGrandchild(Grandchild):
    pass


def test_a_subclass_runs_its_own_copy_of_an_inherited_hot_method():
    assert Child.hot is not Base.hot
    assert Child.hot.__code__ is not Base.hot.__code__
    assert original(Child.hot) is Base.hot
    assert (Child.hot.__name__, Child.hot.__qualname__, Child.hot.__doc__) == (
        "hot",
        "Base.hot",
        "Doubled, plus what a subclass adds.",
    )
    assert Child().hot(3) == 7 and Child().hot(3, k=3) == 10


def test_an_override_is_left_alone_and_its_subclasses_copy_it_with_super_intact():
    assert "hot" in Grandchild.__dict__ and original(Grandchild.hot) is Grandchild.hot
    assert original(GreatGrandchild.hot) is Grandchild.__dict__["hot"]
    assert GreatGrandchild().hot(3) == 107  # super() still starts after Grandchild
