import os
from glob import glob

from setuptools import find_packages, setup

package_name = "lab8"

setup(
    name=package_name,
    version="0.0.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + package_name]),
        ("share/" + package_name, ["package.xml"]),
        (os.path.join("share", package_name, "launch"), glob("launch/*.launch.py")),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="student",
    maintainer_email="student@example.com",
    description="Lab 8",
    license="Apache-2.0",
    entry_points={
        "console_scripts": [
            f"myServer = {package_name}.my_server:main",
            "myClient = " + package_name + ".my_client:main",
        ],
    },
)
