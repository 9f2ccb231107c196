"""What the API's tests share: a virtual campaign of the paper rig."""

from __future__ import annotations

import pytest

import cadcog
from cadcog.validation.campaign import virtual_campaign, write_campaign


@pytest.fixture(scope="module")
def campaign_csv(tmp_path_factory):
    rig = cadcog.load_rig()
    path = tmp_path_factory.mktemp("api") / "campaign.csv"
    write_campaign(path, virtual_campaign(rig, seed=7))
    return path
