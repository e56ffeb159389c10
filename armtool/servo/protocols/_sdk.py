"""Shared glue for the two Dynamixel protocols, which dynamixel-sdk frames for us."""

from __future__ import annotations

from collections.abc import Mapping

from armtool.servo.transport import CommError, CommErrorKind, Port, Transport


class SdkTransport(Transport):
    """PING/READ/WRITE/SYNC_WRITE through dynamixel-sdk's PacketHandler."""

    version = 1.0

    def __init__(self, port: Port) -> None:
        super().__init__(port)
        from dynamixel_sdk import PacketHandler

        self.ph = PacketHandler(self.version)

    def _check(self, sid: int, result: int, what: str) -> None:
        from dynamixel_sdk import COMM_RX_CORRUPT, COMM_SUCCESS

        if result == COMM_SUCCESS:
            return
        self.port.is_using = False  # the SDK leaves it set after some failures
        kind: CommErrorKind = "corrupt" if result == COMM_RX_CORRUPT else "timeout"
        raise CommError(f"ID {sid}: {what}: {self.ph.getTxRxResult(result)}", kind, sid)

    def ping(self, sid: int) -> tuple[int, int]:
        model, result, err = self.ph.ping(self.port, sid)
        self._check(sid, result, "ping")
        return int(model), int(err)

    def read(self, sid: int, addr: int, n: int) -> tuple[bytes, int]:
        data, result, err = self.ph.readTxRx(self.port, sid, addr, n)
        self._check(sid, result, f"read {n} bytes at {addr}")
        return bytes(data), int(err)

    def write(self, sid: int, addr: int, data: bytes) -> int:
        result, err = self.ph.writeTxRx(self.port, sid, addr, len(data), list(data))
        self._check(sid, result, f"write {len(data)} bytes at {addr}")
        return int(err)

    def sync_write(self, addr: int, n: int, data: Mapping[int, bytes]) -> None:
        param: list[int] = []
        for sid, value in data.items():
            param += [sid, *value]
        result = self.ph.syncWriteTxOnly(self.port, addr, n, param, len(param))
        self._check(0xFE, result, "sync write")
