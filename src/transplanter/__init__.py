"""transplanter: from seedling-transplanting mechanism designs to parts a shop can cut."""

__version__ = "0.1.0"
